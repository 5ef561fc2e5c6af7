#include "eval_render.h"

#include "scene_environment.h"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <stdexcept>

#include "frontend/progress_bar.h"
#include "gltf/gltf_loader.h"
#include "render_scene.h"
#include "renderer.h"
#include "thread_pool.h"

namespace partita::eval {

namespace {

using Clock = std::chrono::steady_clock;

/// The progress bar, and the watchdog of a time budget: past `deadline` it cancels the render.
class LabelledBar : public RenderObserver {
  public:
    LabelledBar(const std::string& label, bool quiet, Clock::time_point deadline,
                std::atomic<bool>& cancel)
        : bar_(ProgressBar::stderrIsTerminal()),
          label_(label),
          quiet_(quiet),
          deadline_(deadline),
          cancel_(cancel) {}
    void onProgress(const RenderProgress& p) override {
        if (Clock::now() > deadline_) cancel_ = true;
        if (quiet_) return;
        RenderProgress labelled = p;
        labelled.phase = label_;
        bar_.update(labelled);
    }
    void finish() {
        if (!quiet_) bar_.finish();
    }

  private:
    ProgressBar bar_;
    std::string label_;
    bool quiet_;
    Clock::time_point deadline_;
    std::atomic<bool>& cancel_;
};

/// A render under a time budget that runs past twice its budget plus this is cancelled.
constexpr double kOverrunSeconds = 10;

}  // namespace

std::unique_ptr<RenderScene> loadRenderScene(const std::string& path,
                                             const EnvironmentSettings& environment) {
    SceneData data = loadGltfFile(path);
    for (const auto& w : data.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    attachEnvironment(data, environment);
    return std::make_unique<RenderScene>(std::move(data));
}

TimedRender renderTimed(const RenderScene& scene, const std::string& algorithm,
                        RenderSettings settings, ThreadPool& pool, bool quiet,
                        const std::string& label) {
    settings.previewIntervalSeconds = 0;  // nobody watches; previews would cost resolves
    std::atomic<bool> cancel{false};
    auto start = Clock::now();
    auto deadline =
        settings.budgetKind == BudgetKind::Seconds
            ? start + std::chrono::duration_cast<Clock::duration>(
                          std::chrono::duration<double>(2 * settings.budget + kOverrunSeconds))
            : Clock::time_point::max();
    LabelledBar bar(label, quiet, deadline, cancel);
    TimedRender out;
    try {
        out.result = runRender(scene, algorithm, settings, pool, cancel, bar);
    } catch (const RenderCancelled&) {
        bar.finish();
        throw std::runtime_error(label + " ran past twice its time budget of " +
                                 budgetText(settings) + " plus " +
                                 std::to_string(int(kOverrunSeconds)) + " s: cancelled");
    } catch (...) {
        bar.finish();
        throw;
    }
    out.wallSeconds = std::chrono::duration<double>(Clock::now() - start).count();
    bar.finish();
    return out;
}

std::string budgetText(const RenderSettings& s) {
    char buf[64];
    if (s.budgetKind == BudgetKind::Seconds)
        std::snprintf(buf, sizeof buf, "%.3g s", s.budget);
    else
        std::snprintf(buf, sizeof buf, "%.0f %s", s.budget,
                      s.budgetKind == BudgetKind::SamplesPerPixel ? "spp" : "mpp");
    return buf;
}

}  // namespace partita::eval
