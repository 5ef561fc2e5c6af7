#include "partition/per_pixel_partitions.h"

#include <algorithm>
#include <cmath>

#include "clock.h"
#include "half_split_error.h"
#include "image_metrics.h"
#include "integrators/bdpt/bdpt_passes.h"
#include "integrators/pt/pt_integrator.h"
#include "progress_reporter.h"
#include "rng.h"

namespace partita {

PathType PerPixelPartitions::keyOf(size_t g) {
    PathType key;
    for (size_t i = 0; i < g; ++i) key = key.withVertex(false);
    return key;
}

namespace {

TypeLayers keysOf(const std::vector<Partition>& partitions) {
    std::vector<PathType> keys;
    for (size_t g = 0; g < partitions.size(); ++g)
        if (partitions[g].perPixel) keys.push_back(PerPixelPartitions::keyOf(g));
    return TypeLayers::of(std::move(keys));
}

}  // namespace

const char* perPixelEstimatorName(PerPixelEstimator e) {
    return e == PerPixelEstimator::PathTracer ? "pt" : "bdpt";
}

namespace {

RenderSettings keepingEveryKey(RenderSettings s, const std::vector<Partition>& partitions) {
    s.maxTypeLayers = int(partitions.size());
    return s;
}

/// The per-pixel partitions' images from a resolved per-pixel film (its layers moved out).
std::vector<Image> imagesOf(LayeredImage resolved, const std::vector<Partition>& partitions,
                            int width, int height) {
    std::vector<Image> out(partitions.size());
    for (size_t g = 0; g < partitions.size(); ++g) {
        if (!partitions[g].perPixel) continue;
        const std::string key = PerPixelPartitions::keyOf(g).toString();
        for (auto& layer : resolved.layers)
            if (layer.name == key) out[g] = std::move(layer.image);
        if (out[g].empty()) out[g] = Image(width, height);
    }
    return out;
}

}  // namespace

PerPixelPartitions::PerPixelPartitions(const RenderContext& ctx,
                                       const std::vector<Partition>& partitions,
                                       PerPixelEstimator estimator)
    : partitions_(partitions),
      settings_(keepingEveryKey(ctx.settings, partitions)),
      ctx_{ctx.scene, ctx.camera, settings_, ctx.pool, ctx.cancel, ctx.observer} {
    // The partition of a contribution's type, if it is estimated here: its key; else dropped.
    auto key = [this](PathType& type) {
        for (size_t g = 0; g < partitions_.size(); ++g) {
            if (!partitions_[g].holds(type)) continue;
            if (!partitions_[g].perPixel) return false;
            type = keyOf(g);
            return true;
        }
        return false;
    };
    if (estimator == PerPixelEstimator::PathTracer)
        passes_ = makeRestrictedPathTracerPasses(ctx_, keysOf(partitions_), key);
    else
        passes_ = std::make_unique<BdptPasses>(ctx_, BdptSettings{}, keysOf(partitions_), key);
}

PerPixelPartitions::~PerPixelPartitions() = default;

void PerPixelPartitions::renderPass(SampleRange range, ProgressReporter& progress) {
    const uint64_t most = passes_->maxPassSamples();
    for (uint64_t first = range.first; first < range.end; first += most)
        passes_->renderPass({first, std::min(range.end, first + most)}, progress);
}

std::vector<Image> perPixelImages(const Film& film, const std::vector<Partition>& partitions,
                                  uint64_t spp) {
    return imagesOf(
        film.resolve(spp > 0 ? 1.0f / float(spp) : 0.0f, int(partitions.size()), nullptr),
        partitions, film.width(), film.height());
}

std::vector<Image> PerPixelPartitions::images(uint64_t spp, ThreadPool* pool) const {
    return imagesOf(passes_->resolve(std::max<uint64_t>(spp, 1), pool), partitions_,
                    settings_.width, settings_.height);
}

std::vector<Image> PerPixelPartitions::takeImages(uint64_t spp, ThreadPool* pool) {
    return imagesOf(passes_->takeResolved(std::max<uint64_t>(spp, 1), pool), partitions_,
                    settings_.width, settings_.height);
}

Film PerPixelPartitions::takeFilm() { return passes_->takeFilm(); }

uint64_t PerPixelPartitions::rays() const {
    RenderStats stats;
    passes_->addStats(stats, 0);
    return uint64_t(stats.values["rays"]);
}

void PerPixelPartitions::renderOnlyTiles(std::vector<size_t> tiles) {
    passes_->renderOnlyTiles(std::move(tiles));
}

PilotTiles perPixelPilotTiles(int width, int height) {
    const int tilesX = (width + Film::kTileSize - 1) / Film::kTileSize;
    const int tilesY = (height + Film::kTileSize - 1) / Film::kTileSize;
    PilotTiles out;
    out.pixels = double(width) * double(height);
    const size_t stride = size_t(std::ceil(out.pixels / kPerPixelPilotPixels));
    if (stride <= 1) return out;
    auto tilePixels = [&](size_t t) {
        const int x0 = int(t % size_t(tilesX)) * Film::kTileSize;
        const int y0 = int(t / size_t(tilesX)) * Film::kTileSize;
        return double(std::min(Film::kTileSize, width - x0)) *
               double(std::min(Film::kTileSize, height - y0));
    };
    out.pixels = 0;
    for (size_t t = 0; t < size_t(tilesX) * size_t(tilesY); ++t) {
        if (mix64(t + 0x9117) % stride != 0) continue;
        out.tiles.push_back(t);
        out.pixels += tilePixels(t);
    }
    if (out.tiles.empty()) {
        out.tiles.push_back(0);
        out.pixels = tilePixels(0);
    }
    return out;
}

PerPixelPilot runPerPixelPilot(const RenderContext& ctx, const std::vector<Partition>& partitions,
                               PerPixelEstimator estimator, uint64_t first,
                               ProgressReporter& progress) {
    auto begin = Clock::now();
    std::vector<Partition> all = partitions;
    for (Partition& p : all) p.perPixel = true;
    const PilotTiles pilot = perPixelPilotTiles(ctx.settings.width, ctx.settings.height);
    // Sums over the pilot's pixels stand for the image's: scaled by the ratio of their counts.
    const double scale = double(ctx.settings.width) * ctx.settings.height / pilot.pixels;
    PerPixelPartitions a(ctx, all, estimator), b(ctx, all, estimator);
    a.renderOnlyTiles(pilot.tiles);
    b.renderOnlyTiles(pilot.tiles);
    a.renderPass({first, first + 1}, progress);
    b.renderPass({first + 1, first + 2}, progress);
    const std::vector<Image> ia = a.images(1), ib = b.images(1);
    PerPixelPilot out;
    out.variance.assign(partitions.size(), 0);
    out.varianceRgb.assign(partitions.size(), 0);
    for (size_t g = 0; g < partitions.size(); ++g) {
        out.variance[g] = scale * luminanceSquaredDifference(ia[g], ib[g]) / 2;
        // halvesError's is the variance of the two samples' mean: one sample's is twice it.
        out.varianceRgb[g] = scale * 2 * halvesError(ia[g], ib[g], 1, 1).variance;
    }
    out.raysPerSample = scale * double(a.rays() + b.rays()) / 2;
    out.secondsPerSample = scale * secondsSince(begin) / 2;
    return out;
}

}  // namespace partita
