#include "integrators/sample_passes.h"

#include <algorithm>
#include <ctime>

#include "clock.h"
#include "progress_reporter.h"

namespace partita {

namespace {

class SamplePassLoop {
  public:
    SamplePassLoop(const RenderContext& ctx, SamplePassRenderer& renderer)
        : ctx_(ctx), renderer_(renderer) {}

    RenderResult run() {
        const RenderSettings& s = ctx_.settings;
        bool timed = s.budgetKind == BudgetKind::Seconds;
        uint64_t targetSpp = timed ? UINT64_MAX : uint64_t(s.budget);
        double pixels = double(s.width) * s.height;
        ProgressReporter progress(ctx_.observer, "render", "samples",
                                  timed ? 0 : pixels * double(targetSpp), timed ? s.budget : 0);
        start_ = Clock::now();
        auto lastPreview = start_;
        uint64_t passSpp = 1;
        while (sppDone_ < targetSpp) {
            ctx_.throwIfCancelled();
            uint64_t begin = sppDone_, end = std::min(targetSpp, sppDone_ + passSpp);
            auto passStart = Clock::now();
            std::clock_t passCpuStart = std::clock();
            renderer_.renderPass({begin, end}, progress);
            double passSeconds = secondsSince(passStart);
            renderSeconds_ += passSeconds;
            renderCpuSeconds_ += double(std::clock() - passCpuStart) / CLOCKS_PER_SEC;
            sppDone_ = end;
            double elapsed = secondsSince(start_);
            if (timed && elapsed >= s.budget) break;
            // A first preview right after the first (one-sample) pass, so that a watcher sees
            // the image within a moment of the render starting; then one per interval.
            bool previewDue = s.previewIntervalSeconds > 0 && sppDone_ < targetSpp &&
                              (begin == 0 || secondsSince(lastPreview) >= s.previewIntervalSeconds);
            if (previewDue) {
                lastPreview = Clock::now();
                // Resolved on the pool, which would sit idle meanwhile.
                ctx_.observer.onPreview(renderer_.resolve(sppDone_, &ctx_.pool), stats(elapsed));
            }
            passSpp = nextPassSize(passSeconds / double(end - begin), secondsSince(start_),
                                   secondsSince(lastPreview));
        }
        progress.flush();
        RenderResult result;
        result.image = renderer_.resolve(std::max<uint64_t>(1, sppDone_), nullptr);
        result.stats = stats(secondsSince(start_));
        return result;
    }

  private:
    /// Passes sized to end when the next preview is due (so previews keep to their interval
    /// rather than waiting for a pass to finish), about a second without previews, and never
    /// past a time budget.
    uint64_t nextPassSize(double secondsPerSpp, double elapsed, double sincePreview) const {
        const RenderSettings& s = ctx_.settings;
        double window = s.previewIntervalSeconds > 0
                            ? std::max(0.0, s.previewIntervalSeconds - sincePreview)
                            : 1.0;
        if (s.budgetKind == BudgetKind::Seconds)
            window = std::min(window, std::max(0.0, s.budget - elapsed));
        if (!(secondsPerSpp > 0)) return 1;
        double most = double(std::max<uint64_t>(1, renderer_.maxPassSamples()));
        return uint64_t(std::clamp(window / secondsPerSpp, 1.0, most));
    }

    RenderStats stats(double seconds) const {
        RenderStats st;
        st.values["spp"] = double(sppDone_);
        st.values["seconds"] = seconds;
        // Only the passes: no setup, previews or final resolve (the rate of the sampling). The
        // CPU time (of the whole process, so summed over threads) does not count time when the
        // threads were not running, for rates measured on a busy machine.
        st.values["render_seconds"] = renderSeconds_;
        st.values["render_cpu_seconds"] = renderCpuSeconds_;
        renderer_.addStats(st, seconds);
        return st;
    }

    const RenderContext& ctx_;
    SamplePassRenderer& renderer_;
    Clock::time_point start_;
    uint64_t sppDone_ = 0;
    double renderSeconds_ = 0;     // sum of the passes' wall-clock times
    double renderCpuSeconds_ = 0;  // and of their process CPU times
};

}  // namespace

RenderResult runSamplePasses(const RenderContext& ctx, SamplePassRenderer& renderer) {
    return SamplePassLoop(ctx, renderer).run();
}

}  // namespace partita
