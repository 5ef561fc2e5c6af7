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
    // The most vertices, with g's bits as the specular ones: a distinct key for every g (a
    // count of g vertices would stop at 64), and never a path's type in this film.
    PathType key;
    static_assert(PathType::kMaxScatteringVertices <= 64, "one bit of g a vertex");
    for (int v = 0; v < PathType::kMaxScatteringVertices; ++v)
        key = key.withVertex(((uint64_t(g) >> v) & 1u) != 0);
    return key;
}

namespace {

/// The film's layers: the keys (`keys`[i] = keyOf(i)) of the per-pixel partitions, and with
/// `byParity` their odd samples' too.
TypeLayers layersOf(const std::vector<Partition>& partitions, const std::vector<PathType>& keys,
                    bool byParity) {
    std::vector<PathType> kept;
    for (size_t g = 0; g < partitions.size(); ++g) {
        if (!partitions[g].perPixel) continue;
        kept.push_back(keys[g]);
        if (byParity) kept.push_back(keys[partitions.size() + g]);
    }
    return TypeLayers::of(std::move(kept));
}

}  // namespace

const char* perPixelEstimatorName(PerPixelEstimator e) {
    return e == PerPixelEstimator::PathTracer ? "pt" : "bdpt";
}

namespace {

RenderSettings keepingEveryKey(RenderSettings s, const std::vector<Partition>& partitions) {
    s.maxTypeLayers = 2 * int(partitions.size());  // byParity's too
    return s;
}

/// The per-pixel partitions' images from a resolved per-pixel film (its layers moved out).
std::vector<Image> imagesOf(LayeredImage& resolved, const std::vector<Partition>& partitions,
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
                                       PerPixelEstimator estimator, bool byParity)
    : partitions_(partitions),
      byParity_(byParity),
      settings_(keepingEveryKey(ctx.settings, partitions)),
      ctx_{ctx.scene, ctx.camera, settings_, ctx.pool, ctx.cancel, ctx.observer} {
    for (size_t i = 0; i < 2 * partitions_.size(); ++i) keys_.push_back(keyOf(i));
    // The partition of a contribution's type, if it is estimated here: its key; else dropped.
    auto key = [this](PathType& type, uint64_t sample) {
        for (size_t g = 0; g < partitions_.size(); ++g) {
            if (!partitions_[g].holds(type)) continue;
            if (!partitions_[g].perPixel) return false;
            type = keys_[byParity_ && (sample & 1) ? partitions_.size() + g : g];
            return true;
        }
        return false;
    };
    const TypeLayers layers = layersOf(partitions_, keys_, byParity_);
    if (estimator == PerPixelEstimator::PathTracer)
        passes_ = makeRestrictedPathTracerPasses(ctx_, layers, key);
    else
        passes_ = std::make_unique<BdptPasses>(ctx_, BdptSettings{}, layers, key);
}

PerPixelPartitions::~PerPixelPartitions() = default;

void PerPixelPartitions::renderPass(SampleRange range, ProgressReporter& progress) {
    const uint64_t most = passes_->maxPassSamples();
    for (uint64_t first = range.first; first < range.end; first += most)
        passes_->renderPass({first, std::min(range.end, first + most)}, progress);
}

std::vector<Image> perPixelImages(const Film& film, const std::vector<Partition>& partitions,
                                  uint64_t spp) {
    LayeredImage resolved =
        film.resolve(spp > 0 ? 1.0f / float(spp) : 0.0f, int(partitions.size()), nullptr);
    return imagesOf(resolved, partitions, film.width(), film.height());
}

std::vector<Image> PerPixelPartitions::images(uint64_t spp, ThreadPool* pool) const {
    LayeredImage resolved = passes_->resolve(std::max<uint64_t>(spp, 1), pool);
    return imagesOf(resolved, partitions_, settings_.width, settings_.height);
}

std::vector<Image> PerPixelPartitions::takeImages(uint64_t spp, ThreadPool* pool) {
    LayeredImage resolved = passes_->takeResolved(std::max<uint64_t>(spp, 1), pool);
    return imagesOf(resolved, partitions_, settings_.width, settings_.height);
}

Image parityImage(const Film& film, size_t partitions, size_t g, bool odd, uint64_t perParity) {
    return film.resolveType(PerPixelPartitions::keyOf(odd ? partitions + g : g),
                            1.0f / float(std::max<uint64_t>(perParity, 1)));
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

void PerPixelPartitions::keepOddHalf() { passes_->keepOddHalf(); }

double PerPixelPartitions::perSampleLuminanceVariance(uint64_t spp) const {
    if (spp < 2) return 0;
    HalfSplitError halves;
    halves.setInterleaved(passes_->combinedSums(), passes_->oddHalfSums(), spp);
    return halves.perSampleLuminanceVariance();
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
                               ProgressReporter& progress, uint64_t perParity) {
    auto begin = Clock::now();
    std::vector<Partition> all = partitions;
    for (Partition& p : all) p.perPixel = true;
    const PilotTiles pilot = perPixelPilotTiles(ctx.settings.width, ctx.settings.height);
    // Sums over the pilot's pixels stand for the image's: scaled by the ratio of their counts.
    const double scale = double(ctx.settings.width) * ctx.settings.height / pilot.pixels;
    const uint64_t k = std::max<uint64_t>(perParity, 1);
    PerPixelPartitions pilotRender(ctx, all, estimator, /*byParity=*/true);
    pilotRender.renderOnlyTiles(pilot.tiles);
    pilotRender.renderPass({first, first + 2 * k}, progress);
    const double seconds = secondsSince(begin);
    const Film film = pilotRender.takeFilm();
    PerPixelPilot out;
    out.variance.assign(partitions.size(), 0);
    out.varianceRgb.assign(partitions.size(), 0);
    for (size_t g = 0; g < partitions.size(); ++g) {
        // One partition's two images at a time (at 1920x1080, every partition's at once were
        // ~600 MB for a pilot over 65536 pixels).
        const Image even = parityImage(film, partitions.size(), g, false, k);
        const Image odd = parityImage(film, partitions.size(), g, true, k);
        // One k-sample estimate's variance is half the squared difference of two; one sample's
        // k times it (where the error falls as 1 / n).
        out.variance[g] = scale * double(k) * luminanceSquaredDifference(even, odd) / 2;
        // halvesError's is the variance of the two estimates' mean: one's is twice it.
        out.varianceRgb[g] = scale * double(k) * 2 * halvesError(even, odd, 1, 1).variance;
    }
    out.raysPerSample = scale * double(pilotRender.rays()) / double(2 * k);
    out.secondsPerSample = scale * seconds / double(2 * k);
    return out;
}

}  // namespace partita
