#include "integrators/mlt/direct_light.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <span>
#include <vector>

#include "camera.h"
#include "half_split_error.h"
#include "image_metrics.h"
#include "integrators/pt/pt_integrator.h"
#include "light_emission.h"
#include "mcmc/chain_runner.h"
#include "path/connection.h"
#include "pixel_sample_position.h"
#include "progress_reporter.h"
#include "render_scene.h"
#include "rng.h"
#include "thread_pool.h"

namespace partita {

namespace {

constexpr uint64_t kDirectStreams = 0x444952454354ull;  // "DIRECT": apart from pt's and bdpt's
constexpr uint64_t kScrambleSample = ~uint64_t(0);      // a pixel's scrambles: no sample's index

}  // namespace

PathRestriction indirectLightOnly() {
    return [](const PathType& t) { return !isDirectLightType(t); };
}

DirectLightRenderer::DirectLightRenderer(const RenderContext& ctx, TypeLayers layers,
                                         uint64_t stream)
    : ctx_(ctx),
      film_(ctx.settings.width, ctx.settings.height, std::move(layers)),
      splatBuffer_(ctx.settings.width, ctx.settings.height),
      tiles_(size_t(film_.tilesX()) * size_t(film_.tilesY())) {
    // As bdpt's camera walk (an emitter may be hit one vertex past maxDepth scattering ones),
    // cut after the vertex that follows the first non-specular one.
    walk_.maxVertices = ctx.settings.maxDepth + 2;
    walk_.stopAfterNonSpecular = true;
    lightWalk_.maxVertices = 1;  // the light vertex alone
    streams_ = kDirectStreams ^ (stream * 0x9e3779b97f4a7c15ull);
    for (const Light& light : ctx.scene.lights())
        lightTracing_ = lightTracing_ || (!isHittableLight(light) && cameraCanConnectTo(light));
}

DirectLightRenderer::~DirectLightRenderer() = default;

uint64_t DirectLightRenderer::maxPassSamples() const {
    if (!lightTracing_) return uint64_t(1) << 30;
    // Splats are held for a pass, as bdpt's: about 2^18 pixel samples.
    double pixels = double(film_.width()) * film_.height();
    return uint64_t(std::max(1.0, double(1 << 18) / pixels));
}

void DirectLightRenderer::renderPass(SampleRange range, ProgressReporter* progress) {
    const uint64_t most = maxPassSamples();
    for (uint64_t first = range.first; first < range.end; first += most)
        renderPassPart({first, std::min(range.end, first + most)}, progress);
    if (!keepHalves_ || range.count() == 0) return;
    halves_.addRun(film_.resolveCombined(1.0f), range.count(), nextHalfA_);
    nextHalfA_ = !nextHalfA_;
}

void DirectLightRenderer::renderPassPart(SampleRange range, ProgressReporter* progress) {
    const int tilesX = film_.tilesX();
    ctx_.pool.parallelFor(tiles_.size(), [&](size_t tile) {
        ctx_.throwIfCancelled();
        int x0 = int(tile % size_t(tilesX)) * Film::kTileSize;
        int y0 = int(tile / size_t(tilesX)) * Film::kTileSize;
        int x1 = std::min(x0 + Film::kTileSize, film_.width());
        int y1 = std::min(y0 + Film::kTileSize, film_.height());
        uint64_t rays = 0;
        renderTile(x0, y0, x1, y1, range, tiles_[tile], rays);
        rays_.fetch_add(rays, std::memory_order_relaxed);
        if (progress) progress->advance(double(x1 - x0) * (y1 - y0) * double(range.count()));
    });
    // The light-tracing splats by sample index, and within one tile by tile: a fixed order
    // whatever the threads did, and one group per sample index (splat_buffer.h), so that any
    // split of the samples into passes or shards gives the same film.
    if (!lightTracing_) return;
    for (uint64_t i = 0; i < range.count(); ++i) {
        for (const TileSplats& tile : tiles_)
            for (uint32_t k = tile.sampleStarts[i]; k < tile.sampleStarts[i + 1]; ++k)
                splatBuffer_.addTent(tile.splats[k].raster, PathType{}, tile.splats[k].value);
        splatBuffer_.flushInto(film_);
    }
}

void DirectLightRenderer::renderTile(int x0, int y0, int x1, int y1, SampleRange range,
                                     TileSplats& splats, uint64_t& rays) {
    const RenderScene& scene = ctx_.scene;
    const Camera& camera = ctx_.camera;
    const int width = film_.width(), maxDepth = ctx_.settings.maxDepth;
    Connector connector(scene, camera);
    connector.restrictToPathTracer();
    // Next-event estimation samples its own light vertex; connect() only asks that the light
    // subpath hold s vertices, so one unused vertex stands in for it.
    const PathVertex unusedLightVertex{};
    const std::span<const PathVertex> noLight(&unusedLightVertex, 1);
    std::vector<PathVertex> path, light;
    splats.splats.clear();
    splats.sampleStarts.assign(1, 0);
    // Sample by sample over the tile's pixels, so that the splats come out in sample order.
    for (uint64_t s = range.first; s < range.end; ++s) {
        ctx_.throwIfCancelled();
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                Film::Pixel pixel = film_.pixel(x, y);
                const uint64_t index = uint64_t(y) * uint64_t(width) + uint64_t(x);
                // The raster position stratified over the pixel's samples (the light seen
                // directly has its variance at edges), the rest from the sample's own stream.
                Rng scramble(ctx_.settings.seed,
                             pixelSampleStream(index, kScrambleSample) ^ streams_);
                const uint32_t scrambleX = scramble.nextUInt(), scrambleY = scramble.nextUInt();
                Rng rng(ctx_.settings.seed, pixelSampleStream(index, s) ^ streams_);
                Vec2f u = scrambledSobol02(uint32_t(s), scrambleX, scrambleY);
                Ray primary = camera.generateRay(filteredRasterPosition(x, y, u));
                traceCameraSubpath(scene, camera, primary, rng, walk_, path, rays);
                // x_f, the first non-specular scattering vertex: emitter hits up to x_{f+1} and
                // next-event estimation up to x_f form direct-class paths, nothing beyond.
                const int count = int(path.size());
                int first = count;
                for (int i = 1; i < count; ++i)
                    if (!path[size_t(i)].delta) {
                        first = i;
                        break;
                    }
                for (int t = 2; t <= count; ++t)
                    for (int strategy = 0; strategy <= 1; ++strategy) {
                        if (strategy + t - 2 > maxDepth || t > first + 2 - strategy) continue;
                        StrategySample c = connector.connect(path, noLight, strategy, t, rng, rays);
                        if (!c.valid || !(c.weight > 0) || !isDirectLightType(c.type)) continue;
                        pixel.add(c.type, c.value * c.weight);
                    }
                if (!lightTracing_) continue;
                // L E from a light no camera ray can hit (a point or spot light): light tracing
                // (s = 1, t = 1) is the only strategy that samples it, so its weight is 1; a
                // hittable light's L E is the emitter hit's above, with weight 1 among the path
                // tracer's strategies, and is not splatted.
                traceLightSubpath(scene, rng, lightWalk_, light, rays);
                if (light.empty() || isHittableLight(scene.lights()[size_t(light[0].light)]))
                    continue;
                StrategySample c = connector.connect(path, light, 1, 1, rng, rays, false);
                if (c.valid) splats.splats.push_back({c.raster, c.value});
            }
        splats.sampleStarts.push_back(uint32_t(splats.splats.size()));
    }
}

void DirectLightRenderer::absorb(const DirectLightRenderer& other) {
    film_.merge(other.film_);
    rays_.fetch_add(other.rays(), std::memory_order_relaxed);
}

DirectPilot runDirectPilot(const RenderContext& ctx, ProgressReporter* progress) {
    auto begin = std::chrono::steady_clock::now();
    constexpr uint64_t kPilotStream = 1;
    DirectPilot out;
    // Sample `index` of every pixel; its combined image is all the pilot needs (no type layers).
    auto sample = [&](uint64_t index) {
        DirectLightRenderer renderer(ctx, TypeLayers::of({}), kPilotStream);
        renderer.renderPass({index, index + 1}, progress);
        out.rays += double(renderer.rays());
        return renderer.film().resolveCombined(1.0f);
    };
    Image a = sample(0);
    const Image b = sample(1);
    out.variance = luminanceSquaredDifference(a, b) / 2;
    out.errorSums = halvesError(a, b, 1, 1);
    for (size_t i = 0; i < a.rgb.size(); ++i) a.rgb[i] = 0.5f * (a.rgb[i] + b.rgb[i]);
    out.image = std::move(a);
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    return out;
}

double chainHalvesError(const Film& all, const Film& half, uint64_t mutationsA, uint64_t mutationsB,
                        double bValue, int width, int height) {
    if (mutationsA == 0 || mutationsB == 0) return 0;
    const auto [a, b] = filmHalves(all, half, bValue, width, height, mutationsA, mutationsB);
    return luminanceSquaredDifference(a, b) / 4;
}

double pooledDirectVariance(double pilotVariance, const HalfSplitError& own) {
    constexpr double kPilotSamples = 2;
    return pooledVariance(pilotVariance, kPilotSamples, own.perSampleLuminanceVariance(),
                          double(own.samplesA() + own.samplesB()));
}

uint64_t neymanDirectSpp(double directVariance, double directCost, double chainError,
                         double chainCost, uint64_t lo, uint64_t hi) {
    if (!(chainError > 0) || !(chainCost > 0) || !(directCost > 0) || !(directVariance >= 0))
        return lo;
    double n = std::sqrt(directVariance * chainCost / (chainError * directCost));
    if (!std::isfinite(n)) return hi;
    return uint64_t(std::clamp(std::ceil(n), double(lo), double(hi)));
}

double neymanDirectShare(double directVariance, double directCost, double chainError,
                         double chainCost) {
    const double ad = std::sqrt(std::max(0.0, directVariance * directCost));
    const double ac = std::sqrt(std::max(0.0, chainError * chainCost));
    if (!(ac > 0)) return 1;
    return ad / (ad + ac);
}

LayeredImage resolveDirectLight(const Film& film, uint64_t spp, int maxTypeLayers,
                                ThreadPool* pool) {
    return film.resolve(spp > 0 ? 1.0f / float(spp) : 0.0f, maxTypeLayers, pool);
}

LayeredImage addDisjointParts(LayeredImage a, LayeredImage b, int maxTypeLayers) {
    // The parts' images are moved into the sum, not copied (a 1080p layer is 25 MB).
    LayeredImage out;
    out.combined = std::move(a.combined);
    if (out.combined.empty())
        out.combined = std::move(b.combined);
    else if (!b.combined.empty())
        for (size_t i = 0; i < out.combined.rgb.size(); ++i)
            out.combined.rgb[i] += b.combined.rgb[i];

    struct Ranked {
        PathType type;
        double total;
        Image* image;
    };
    std::vector<Ranked> ranked;
    std::vector<const Image*> others;  // a's "other", then b's
    for (LayeredImage* part : {&a, &b})
        for (ImageLayer& layer : part->layers) {
            PathType type;
            if (layer.name == Film::kOtherLayer || !PathType::parse(layer.name, type)) {
                others.push_back(&layer.image);
                continue;
            }
            double total = 0;  // in pixel order, as Film::resolve sums a type's luminance
            for (size_t i = 0; i + 2 < layer.image.rgb.size(); i += 3)
                total += luminance(
                    Rgb(layer.image.rgb[i], layer.image.rgb[i + 1], layer.image.rgb[i + 2]));
            ranked.push_back({type, total, &layer.image});
        }
    // Largest total first, ties in PathType order (a stable sort of the types in that order).
    std::sort(ranked.begin(), ranked.end(),
              [](const Ranked& x, const Ranked& y) { return x.type < y.type; });
    std::stable_sort(ranked.begin(), ranked.end(),
                     [](const Ranked& x, const Ranked& y) { return x.total > y.total; });
    const size_t keep = std::min(ranked.size(), size_t(std::max(0, maxTypeLayers)));
    for (size_t i = 0; i < keep; ++i)
        out.layers.push_back({ranked[i].type.toString(), std::move(*ranked[i].image)});
    // "other": both parts' own, then the types left out in PathType order.
    std::vector<const Ranked*> dropped;
    for (size_t i = keep; i < ranked.size(); ++i) dropped.push_back(&ranked[i]);
    std::sort(dropped.begin(), dropped.end(),
              [](const Ranked* x, const Ranked* y) { return x->type < y->type; });
    for (const Ranked* r : dropped) others.push_back(r->image);
    if (!others.empty()) {
        Image other(out.combined.width, out.combined.height);
        for (const Image* image : others)
            for (size_t i = 0; i < other.rgb.size() && i < image->rgb.size(); ++i)
                other.rgb[i] += image->rgb[i];
        out.layers.push_back({Film::kOtherLayer, std::move(other)});
    }
    return out;
}

}  // namespace partita
