#include "integrators/pt/pt_integrator.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <optional>

#include "camera.h"
#include "film.h"
#include "integrators/pt/film_sink.h"
#include "integrators/pt/path_sampler.h"
#include "integrators/sample_passes.h"
#include "pixel_sample_position.h"
#include "progress_reporter.h"
#include "render_scene.h"
#include "sampling.h"
#include "thread_pool.h"

namespace partita {

Vec2f filteredRasterPosition(int x, int y, Vec2f u) {
    return {float(x) + 0.5f + sampleTent(u.x), float(y) + 0.5f + sampleTent(u.y)};
}

namespace {

class PathTracerPasses : public SamplePassRenderer {
  public:
    PathTracerPasses(const RenderContext& ctx, const TypeLayers& layers, ContributionKey key = {})
        : ctx_(ctx), key_(std::move(key)), film_(ctx.settings.width, ctx.settings.height, layers) {
        samplerSettings_.maxDepth = ctx.settings.maxDepth;
    }

    void renderPass(SampleRange range, ProgressReporter& progress) override {
        int tilesX = film_.tilesX();
        size_t tileCount = only_.empty() ? size_t(tilesX) * film_.tilesY() : only_.size();
        ctx_.pool.parallelFor(tileCount, [&](size_t i) {
            ctx_.throwIfCancelled();
            const size_t tile = only_.empty() ? i : only_[i];
            int x0 = int(tile % tilesX) * Film::kTileSize,
                y0 = int(tile / tilesX) * Film::kTileSize;
            int x1 = std::min(x0 + Film::kTileSize, film_.width());
            int y1 = std::min(y0 + Film::kTileSize, film_.height());
            PathCounters counters;
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; x += kPacketWidth)
                    renderPixelRun(x, y, std::min(kPacketWidth, x1 - x), range, counters);
            rays_.fetch_add(counters.rays, std::memory_order_relaxed);
            progress.advance(double(x1 - x0) * (y1 - y0) * double(range.count()));
        });
    }

    LayeredImage resolve(uint64_t samples, ThreadPool* pool) const override {
        return film_.resolve(1.0f / float(samples), ctx_.settings.maxTypeLayers, pool);
    }

    LayeredImage takeResolved(uint64_t samples, ThreadPool* pool) override {
        return film_.takeResolved(1.0f / float(samples), ctx_.settings.maxTypeLayers, pool);
    }

    void keepOddHalf() override {
        if (!oddHalf_) oddHalf_.emplace(film_.width(), film_.height(), TypeLayers::of({}));
    }
    Image combinedSums() const override { return film_.resolveCombined(1.0f); }
    Image oddHalfSums() const override {
        return oddHalf_ ? oddHalf_->resolveCombined(1.0f) : Image(film_.width(), film_.height());
    }

    void renderOnlyTiles(std::vector<size_t> tiles) override { only_ = std::move(tiles); }

    Film film() const override {
        Film copy(film_.width(), film_.height(), film_.layers());
        copy.merge(film_);
        return copy;
    }
    Film takeFilm() override { return std::move(film_); }

    void addStats(RenderStats& st, double seconds) const override {
        st.values["rays"] = double(rays_.load());
        st.values["rays_per_second"] = seconds > 0 ? double(rays_.load()) / seconds : 0;
        st.values["path_types"] = double(film_.typeCount());
        st.values["dropped_samples"] = double(film_.droppedSamples());
    }

  private:
    static constexpr int kPacketWidth = 8;  // pixels whose camera rays form one Embree packet

    /// Pixels (x, y) to (x + n - 1, y), n <= kPacketWidth, sample by sample. The n camera rays
    /// of one sample index are traced as one packet (neighbouring camera rays are coherent, so
    /// Embree's packet kernel traverses the BVH for all of them at once), and the paths then
    /// continue two at a time in lockstep (samplePathPair). Every pixel draws its random numbers
    /// from its own stream and gets its samples in index order, so its sums do not depend on
    /// how pixels are grouped.
    void renderPixelRun(int x, int y, int n, SampleRange range, PathCounters& counters) {
        std::array<std::optional<FilmSink>, kPacketWidth> sinks;
        for (int i = 0; i < n; ++i)
            sinks[size_t(i)].emplace(film_, x + i, y, key_ ? &key_ : nullptr,
                                     oddHalf_ ? &*oddHalf_ : nullptr);
        std::array<Rng, kPacketWidth> rngs;
        std::array<Ray, kPacketWidth> rays;
        std::array<SurfaceHit, kPacketWidth> hits;
        bool found[kPacketWidth];
        for (uint64_t s = range.first; s < range.end; ++s) {
            for (int i = 0; i < n; ++i) {
                sinks[size_t(i)]->selectSample(s);
                rngs[size_t(i)] = pixelSampleRng(ctx_.settings.seed, x + i, y, film_.width(), s);
                const uint64_t pixelIndex = uint64_t(y) * uint64_t(film_.width()) + uint64_t(x + i);
                Vec2f u = pixelSamplePosition(ctx_.settings.seed, pixelIndex, s);
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

    const RenderContext& ctx_;
    ContributionKey key_;
    Film film_;
    std::optional<Film> oddHalf_;  // the odd sample indices' combined sums (keepOddHalf)
    std::vector<size_t> only_;     // the tiles a pass renders (renderOnlyTiles); empty: all
    PathSamplerSettings samplerSettings_;
    std::atomic<uint64_t> rays_{0};
};

std::unique_ptr<SamplePassRenderer> makePathTracerPasses(const RenderContext& ctx,
                                                         const TypeLayers& layers) {
    return std::make_unique<PathTracerPasses>(ctx, layers);
}

}  // namespace

std::unique_ptr<SamplePassRenderer> makeRestrictedPathTracerPasses(const RenderContext& ctx,
                                                                   const TypeLayers& layers,
                                                                   ContributionKey key) {
    return std::make_unique<PathTracerPasses>(ctx, layers, std::move(key));
}

PathTracerAlgorithm::PathTracerAlgorithm(SamplePassSettings settings) : settings_(settings) {}
PathTracerAlgorithm::~PathTracerAlgorithm() = default;

RenderResult PathTracerAlgorithm::render(const RenderContext& ctx) {
    return renderSamplePasses(ctx, makePathTracerPasses, settings_);
}

Shardable* PathTracerAlgorithm::shardable() {
    if (!shards_) shards_ = std::make_unique<SamplePassShards>(makePathTracerPasses, settings_);
    return shards_.get();
}

void registerPathTracer() {
    // The shared parameters (render_settings.h) and the sample-pass loop's (target_error).
    AlgorithmRegistry::instance().add(algorithmEntry<PathTracerAlgorithm>(
        "pt",
        "unidirectional path tracer with next-event estimation and MIS "
        "(the reference; per-type layers)",
        BudgetKind::SamplesPerPixel, samplePassParameters(), /*orthographicCamera=*/true));
}

}  // namespace partita
