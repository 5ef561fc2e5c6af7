#include "eval_render.h"

#include "scene_environment.h"

#include <atomic>
#include <chrono>
#include <cstdio>

#include "frontend/progress_bar.h"
#include "gltf/gltf_loader.h"
#include "render_scene.h"
#include "renderer.h"
#include "thread_pool.h"

namespace partita::eval {

namespace {

class LabelledBar : public RenderObserver {
  public:
    LabelledBar(const std::string& label, bool quiet)
        : bar_(ProgressBar::stderrIsTerminal()), label_(label), quiet_(quiet) {}
    void onProgress(const RenderProgress& p) override {
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
};

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
    LabelledBar bar(label, quiet);
    auto start = std::chrono::steady_clock::now();
    TimedRender out;
    try {
        out.result = runRender(scene, algorithm, settings, pool, cancel, bar);
    } catch (...) {
        bar.finish();
        throw;
    }
    out.wallSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
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
