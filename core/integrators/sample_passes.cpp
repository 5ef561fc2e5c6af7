#include "integrators/sample_passes.h"

#include <algorithm>
#include <ctime>
#include <stdexcept>

#include "byte_stream.h"
#include "clock.h"
#include "half_split_error.h"
#include "integrators/layer_survey.h"
#include "mcmc/chain_error_monitor.h"
#include "preview_schedule.h"
#include "progress_reporter.h"
#include "thread_pool.h"

namespace partita {

namespace {

class SamplePassLoop {
  public:
    SamplePassLoop(const RenderContext& ctx, SamplePassRenderer& renderer,
                   const SamplePassSettings& settings)
        : ctx_(ctx), renderer_(renderer), settings_(settings) {}

    RenderResult run() {
        const RenderSettings& s = ctx_.settings;
        bool timed = s.budgetKind == BudgetKind::Seconds;
        uint64_t targetSpp = timed ? UINT64_MAX : uint64_t(s.budget);
        double pixels = double(s.width) * s.height;
        ProgressReporter progress(ctx_.observer, "render", "samples",
                                  timed ? 0 : pixels * double(targetSpp), timed ? s.budget : 0);
        start_ = Clock::now();
        PreviewSchedule previews(ctx_);
        uint64_t passSpp = 1;
        renderer_.keepOddHalf();
        while (sppDone_ < targetSpp) {
            ctx_.throwIfCancelled();
            const uint64_t begin = sppDone_;
            const uint64_t end = std::min(targetSpp, sppDone_ + passSpp);
            auto passStart = Clock::now();
            std::clock_t passCpuStart = std::clock();
            renderAndEstimate({begin, end}, progress);
            double passSeconds = secondsSince(passStart);
            renderSeconds_ += passSeconds;
            renderCpuSeconds_ += double(std::clock() - passCpuStart) / CLOCKS_PER_SEC;
            sppDone_ = end;
            if (reachedTarget()) break;
            double elapsed = secondsSince(start_);
            if (timed && elapsed >= s.budget) break;
            // A first preview right after the first (one-sample) pass, so that a watcher sees
            // the image within a moment of the render starting; then as the schedule says.
            if (sppDone_ < targetSpp && previews.due()) {
                const auto began = Clock::now();
                // Resolved on the pool, which would sit idle meanwhile.
                ctx_.observer.onPreview(renderer_.resolve(sppDone_, &ctx_.pool), stats(elapsed));
                previews.shown(began);
            }
            passSpp =
                nextPassSize(passSeconds / double(end - begin), secondsSince(start_), previews);
        }
        finishEstimate(progress);
        progress.flush();
        RenderResult result;
        result.stats = stats(secondsSince(start_));  // before the film is consumed
        result.image = renderer_.takeResolved(std::max<uint64_t>(1, sppDone_), &ctx_.pool);
        result.stats.values["seconds"] = secondsSince(start_);
        return result;
    }

  private:
    /// Renders the pass, then estimates the error from the even (half A) and odd (half B)
    /// sample indices' sums (half_split_error.h) and reports it. A pass is rendered whole, so
    /// that each pixel gets its samples one after another while its sums are in the cache
    /// (sample by sample over the image, the path tracer lost a tenth of its speed).
    /// The estimate follows every pass while a target error is watched (it may stop the
    /// render), else the chains' monitor's rule (at most every half second, at most 5% of the
    /// time): it resolves two images on one thread, ~0.1 s at 1280x720, where a pass may take
    /// half a second. The last one is made at the end (finishEstimate).
    void renderAndEstimate(SampleRange pass, ProgressReporter& progress) {
        renderer_.renderPass(pass, progress);
        if (settings_.targetError > 0 || !errorEstimate_.ready() || estimates_.due())
            estimate(pass.end, progress);
    }

    void estimate(uint64_t samples, ProgressReporter& progress) {
        const auto begin = Clock::now();
        errorEstimate_.setInterleaved(renderer_.combinedSums(), renderer_.oddHalfSums(), samples);
        estimatedSpp_ = samples;
        if (errorEstimate_.ready())
            progress.setValues({{"error_estimate", errorEstimate_.relativeRmse()}});
        estimates_.ran(begin);
    }

    /// The final image's estimate, for its statistics and the last progress report.
    void finishEstimate(ProgressReporter& progress) {
        if (sppDone_ > 0 && estimatedSpp_ != sppDone_) estimate(sppDone_, progress);
    }

    /// Whether the estimate reached the target error (trusted from kMinHalfSamples samples per
    /// pixel in each half).
    bool reachedTarget() {
        reachedTarget_ = settings_.targetError > 0 &&
                         errorEstimate_.ready(SamplePassSettings::kMinHalfSamples) &&
                         errorEstimate_.relativeRmse() <= settings_.targetError;
        return reachedTarget_;
    }

    /// Passes sized to end when the next preview is due (so previews keep to their interval
    /// rather than waiting for a pass to finish), about kPassSecondsWithoutPreviews when no
    /// preview is wanted, and never past a time budget.
    uint64_t nextPassSize(double secondsPerSpp, double elapsed,
                          const PreviewSchedule& previews) const {
        const RenderSettings& s = ctx_.settings;
        double window = previews.enabled() ? previews.untilDue() : kPassSecondsWithoutPreviews;
        if (s.budgetKind == BudgetKind::Seconds)
            window = std::min(window, std::max(0.0, s.budget - elapsed));
        if (!(secondsPerSpp > 0)) return 1;
        double most = double(std::max<uint64_t>(1, renderer_.maxPassSamples()));
        // With a target error, the estimate is looked at after each pass: a pass of at most a
        // quarter of the samples so far overshoots the target by at most that much.
        if (settings_.targetError > 0) most = std::min(most, std::max(1.0, double(sppDone_) / 4));
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
        if (errorEstimate_.ready()) st.values["error_estimate"] = errorEstimate_.relativeRmse();
        if (settings_.targetError > 0) st.values["reached_target_error"] = reachedTarget_ ? 1 : 0;
        return st;
    }

    const RenderContext& ctx_;
    SamplePassRenderer& renderer_;
    const SamplePassSettings settings_;
    HalfSplitError errorEstimate_;
    uint64_t estimatedSpp_ = 0;  // the samples per pixel of the last estimate
    CostBoundedSchedule estimates_ = ChainErrorMonitor::estimateSchedule();
    bool reachedTarget_ = false;
    Clock::time_point start_;
    uint64_t sppDone_ = 0;
    double renderSeconds_ = 0;     // sum of the passes' wall-clock times
    double renderCpuSeconds_ = 0;  // and of their process CPU times
};

}  // namespace

RenderResult runSamplePasses(const RenderContext& ctx, SamplePassRenderer& renderer,
                             const SamplePassSettings& settings) {
    return SamplePassLoop(ctx, renderer, settings).run();
}

RenderResult renderSamplePasses(const RenderContext& ctx, const SamplePassFactory& factory,
                                const SamplePassSettings& settings) {
    const TypeLayers layers = surveyTypeLayers(ctx, factory);
    std::unique_ptr<SamplePassRenderer> renderer = factory(ctx, layers);
    return runSamplePasses(ctx, *renderer, settings);
}

namespace {

uint64_t sampleBudget(const RenderContext& ctx) {
    if (ctx.settings.budgetKind != BudgetKind::SamplesPerPixel)
        throw std::invalid_argument(
            "a sharded pt/bdpt job needs a samples-per-pixel budget (--spp): a time budget is "
            "not reproducible across machines");
    return uint64_t(ctx.settings.budget);
}

constexpr uint32_t kPlanMagic = 0x4c505350;  // "PSPL"
constexpr uint32_t kPlanVersion = 1;

TypeLayers planLayers(std::span<const uint8_t> plan) {
    ByteReader r(plan, "sample-pass plan");
    r.expectHeader(kPlanMagic, kPlanVersion, "sample-pass plan");
    TypeLayers layers = TypeLayers::deserialize(r);
    if (!r.atEnd()) r.fail("trailing bytes");
    return layers;
}

}  // namespace

std::vector<uint8_t> SamplePassShards::plan(const RenderContext& ctx) {
    sampleBudget(ctx);
    if (settings_.targetError > 0)
        throw std::invalid_argument(
            "a sharded pt/bdpt job renders its whole budget: leave target_error at 0");
    // The only thing fixed once: which types keep a layer. Every (pixel, sample) has its own
    // stream.
    ByteWriter w;
    w.putHeader(kPlanMagic, kPlanVersion);
    surveyTypeLayers(ctx, factory_).serialize(w);
    return std::move(w.bytes);
}

uint32_t SamplePassShards::maxShards(const RenderContext& ctx, std::span<const uint8_t>) const {
    return uint32_t(std::min<uint64_t>(sampleBudget(ctx), UINT32_MAX));
}

ShardWork SamplePassShards::renderShard(const RenderContext& ctx, std::span<const uint8_t> plan,
                                        uint32_t shard, uint32_t shards) {
    const ShareRange share = shareRange(sampleBudget(ctx), shards, shard);
    std::unique_ptr<SamplePassRenderer> renderer = factory_(ctx, planLayers(plan));
    const double pixels = double(ctx.settings.width) * ctx.settings.height;
    ProgressReporter progress(ctx.observer, "render", "samples", pixels * double(share.count()));
    const uint64_t passSpp = std::max<uint64_t>(1, renderer->maxPassSamples());
    for (uint64_t first = share.first; first < share.end; first += passSpp) {
        ctx.throwIfCancelled();
        renderer->renderPass({first, std::min(share.end, first + passSpp)}, progress);
    }
    progress.flush();
    RenderStats stats;
    renderer->addStats(stats, 0);
    ShardWork work;
    work.films.push_back(renderer->takeFilm());
    work.counts.push_back(share.count());
    work.sums["rays"] = stats.values["rays"];
    return work;
}

RenderResult SamplePassShards::resolve(const RenderContext& ctx, std::span<const uint8_t>,
                                       const ShardWork& merged) {
    // As SamplePassLoop's final image: the film over the samples per pixel, without a pool.
    const uint64_t spp = std::max<uint64_t>(1, merged.counts.at(0));
    const Film& film = merged.films.at(0);
    RenderResult result;
    result.image = film.resolve(1.0f / float(spp), ctx.settings.maxTypeLayers, nullptr);
    result.stats.values["spp"] = double(merged.counts[0]);
    result.stats.values["rays"] = merged.sums.count("rays") ? merged.sums.at("rays") : 0;
    result.stats.values["path_types"] = double(film.typeCount());
    result.stats.values["dropped_samples"] = double(film.droppedSamples());
    return result;
}

}  // namespace partita
