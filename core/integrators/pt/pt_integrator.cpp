#include "integrators/pt/pt_integrator.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <ctime>
#include <optional>

#include "camera.h"
#include "film.h"
#include "integrators/pt/film_sink.h"
#include "integrators/pt/path_sampler.h"
#include "progress_reporter.h"
#include "render_scene.h"
#include "sampling.h"
#include "thread_pool.h"

namespace partita {

Vec2f filteredRasterPosition(int x, int y, Vec2f u) {
    return {float(x) + 0.5f + sampleTent(u.x), float(y) + 0.5f + sampleTent(u.y)};
}

namespace {

struct PassRange {
    uint64_t firstSample, endSample;
};

class PathTracerRun {
  public:
    explicit PathTracerRun(const RenderContext& ctx)
        : ctx_(ctx), film_(ctx.settings.width, ctx.settings.height) {
        samplerSettings_.maxDepth = ctx.settings.maxDepth;
    }

    RenderResult run() {
        const RenderSettings& s = ctx_.settings;
        bool timed = s.budgetKind == BudgetKind::Seconds;
        uint64_t targetSpp = timed ? UINT64_MAX : uint64_t(s.budget);
        double pixels = double(s.width) * s.height;
        ProgressReporter progress(ctx_.observer, "render", "samples",
                                  timed ? 0 : pixels * double(targetSpp), timed ? s.budget : 0);
        auto start = std::chrono::steady_clock::now();
        auto lastPreview = start;
        uint64_t passSpp = 1;
        while (sppDone_ < targetSpp) {
            ctx_.throwIfCancelled();
            uint64_t begin = sppDone_, end = std::min(targetSpp, sppDone_ + passSpp);
            auto passStart = std::chrono::steady_clock::now();
            std::clock_t passCpuStart = std::clock();
            renderPass({begin, end}, progress);
            double passSeconds = secondsSince(passStart);
            renderSeconds_ += passSeconds;
            renderCpuSeconds_ += double(std::clock() - passCpuStart) / CLOCKS_PER_SEC;
            sppDone_ = end;
            double elapsed = secondsSince(start);
            if (timed && elapsed >= s.budget) break;
            // A first preview right after the first (one-sample) pass, so that a watcher sees
            // the image within a moment of the render starting; then one per interval.
            bool previewDue = s.previewIntervalSeconds > 0 && sppDone_ < targetSpp &&
                              (begin == 0 || secondsSince(lastPreview) >= s.previewIntervalSeconds);
            if (previewDue) {
                lastPreview = std::chrono::steady_clock::now();
                // Resolved on the pool, which would sit idle meanwhile.
                ctx_.observer.onPreview(
                    film_.resolve(1.0f / float(sppDone_), s.maxTypeLayers, &ctx_.pool),
                    stats(elapsed));
            }
            passSpp = nextPassSize(passSeconds / double(end - begin), secondsSince(start),
                                   secondsSince(lastPreview));
        }
        progress.flush();
        RenderResult result;
        result.image =
            film_.resolve(1.0f / float(std::max<uint64_t>(1, sppDone_)), s.maxTypeLayers);
        result.stats = stats(secondsSince(start));
        return result;
    }

  private:
    static double secondsSince(std::chrono::steady_clock::time_point t) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    }

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
        return uint64_t(std::clamp(window / secondsPerSpp, 1.0, 1024.0));
    }

    void renderPass(PassRange range, ProgressReporter& progress) {
        int tilesX = film_.tilesX();
        size_t tileCount = size_t(tilesX) * film_.tilesY();
        ctx_.pool.parallelFor(tileCount, [&](size_t tile) {
            ctx_.throwIfCancelled();
            int x0 = int(tile % tilesX) * Film::kTileSize,
                y0 = int(tile / tilesX) * Film::kTileSize;
            int x1 = std::min(x0 + Film::kTileSize, film_.width());
            int y1 = std::min(y0 + Film::kTileSize, film_.height());
            PathCounters counters;
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; x += kPacketWidth)
                    renderPixelRun(x, y, std::min(kPacketWidth, x1 - x), range, counters);
            rays_.fetch_add(counters.rays, std::memory_order_relaxed);
            progress.advance(double(x1 - x0) * (y1 - y0) *
                             double(range.endSample - range.firstSample));
        });
    }

    static constexpr int kPacketWidth = 8;  // pixels whose camera rays form one Embree packet

    /// Pixels (x, y) to (x + n - 1, y), n <= kPacketWidth, sample by sample. The n camera rays
    /// of one sample index are traced as one packet (neighbouring camera rays are coherent, so
    /// Embree's packet kernel traverses the BVH for all of them at once), and the paths then
    /// continue two at a time in lockstep (samplePathPair). Every pixel draws its random numbers
    /// from its own stream and gets its samples in index order, so its sums do not depend on
    /// how pixels are grouped.
    void renderPixelRun(int x, int y, int n, PassRange range, PathCounters& counters) {
        std::array<std::optional<FilmSink>, kPacketWidth> sinks;
        for (int i = 0; i < n; ++i) sinks[size_t(i)].emplace(film_, x + i, y);
        std::array<Rng, kPacketWidth> rngs;
        std::array<Ray, kPacketWidth> rays;
        std::array<SurfaceHit, kPacketWidth> hits;
        bool found[kPacketWidth];
        for (uint64_t s = range.firstSample; s < range.endSample; ++s) {
            for (int i = 0; i < n; ++i) {
                rngs[size_t(i)] = pixelSampleRng(ctx_.settings.seed, x + i, y, film_.width(), s);
                Vec2f u{rngs[size_t(i)].nextFloat(), rngs[size_t(i)].nextFloat()};
                rays[size_t(i)] = ctx_.camera.generateRay(filteredRasterPosition(x + i, y, u));
            }
            ctx_.scene.intersect8(rays.data(), n, hits.data(), found);
            auto path = [&](int i) {
                return PathStart{rays[size_t(i)], rngs[size_t(i)], *sinks[size_t(i)], true,
                                 found[i] ? &hits[size_t(i)] : nullptr};
            };
            int i = 0;
            for (; i + 1 < n; i += 2)
                samplePathPair(ctx_.scene, path(i), path(i + 1), samplerSettings_, counters);
            if (i < n) samplePath(ctx_.scene, path(i), samplerSettings_, counters);
        }
    }

    RenderStats stats(double seconds) const {
        RenderStats st;
        st.values["spp"] = double(sppDone_);
        st.values["rays"] = double(rays_.load());
        st.values["seconds"] = seconds;
        // Only the passes: no setup, previews or final resolve (the ray rate of the sampling).
        // The CPU time (of the whole process, so summed over threads) does not count time when
        // the threads were not running, for rates measured on a busy machine.
        st.values["render_seconds"] = renderSeconds_;
        st.values["render_cpu_seconds"] = renderCpuSeconds_;
        st.values["rays_per_second"] = seconds > 0 ? double(rays_.load()) / seconds : 0;
        st.values["path_types"] = double(film_.typeCount());
        st.values["dropped_samples"] = double(film_.droppedSamples());
        return st;
    }

    const RenderContext& ctx_;
    Film film_;
    PathSamplerSettings samplerSettings_;
    uint64_t sppDone_ = 0;
    double renderSeconds_ = 0;     // sum of the passes' wall-clock times
    double renderCpuSeconds_ = 0;  // and of their process CPU times
    std::atomic<uint64_t> rays_{0};
};

}  // namespace

RenderResult PathTracerAlgorithm::render(const RenderContext& ctx) {
    return PathTracerRun(ctx).run();
}

void registerPathTracer() {
    AlgorithmRegistry::instance().add(
        {"pt",
         "unidirectional path tracer with next-event estimation and MIS "
         "(the reference; per-type layers)",
         BudgetKind::SamplesPerPixel, [] { return std::make_unique<PathTracerAlgorithm>(); }});
}

}  // namespace partita
