#include "integrators/bdpt/bdpt_passes.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "camera.h"
#include "integrators/pt/pt_integrator.h"
#include "path/connection.h"
#include "pixel_sample_position.h"
#include "progress_reporter.h"
#include "render_scene.h"
#include "thread_pool.h"

namespace partita {

BdptPasses::BdptPasses(const RenderContext& ctx, const BdptSettings& settings,
                       const TypeLayers& layers, ContributionKey key)
    : ctx_(ctx),
      settings_(settings),
      key_(std::move(key)),
      film_(ctx.settings.width, ctx.settings.height, layers),
      splatBuffer_(ctx.settings.width, ctx.settings.height),
      tiles_(size_t(film_.tilesX()) * film_.tilesY()) {
    // Scattering vertices <= maxDepth: a camera subpath may end on an emitter one vertex
    // further (s = 0), a light subpath needs at most maxDepth surface vertices.
    cameraWalk_.maxVertices = ctx.settings.maxDepth + 2;
    lightWalk_.maxVertices = ctx.settings.maxDepth + 1;
    cameraWalk_.rouletteStartDepth = lightWalk_.rouletteStartDepth = settings.rouletteStartDepth;
    renderOnlyTiles({});
}

void BdptPasses::renderPass(SampleRange range, ProgressReporter& progress) {
    const size_t tilesX = size_t(film_.tilesX());
    for (size_t first = 0; first < order_.size(); first += kBatchTiles) {
        const size_t end = std::min(order_.size(), first + kBatchTiles);
        ctx_.pool.parallelFor(end - first, [&](size_t i) {
            ctx_.throwIfCancelled();
            const size_t tile = order_[first + i];
            int x0 = int(tile % tilesX) * Film::kTileSize,
                y0 = int(tile / tilesX) * Film::kTileSize;
            int x1 = std::min(x0 + Film::kTileSize, film_.width());
            int y1 = std::min(y0 + Film::kTileSize, film_.height());
            renderTile(x0, y0, x1, y1, range, tiles_[tile]);
            progress.advance(double(x1 - x0) * (y1 - y0) * double(range.count()));
        });
        addSplats(range, std::span<const size_t>(order_).subspan(first, end - first));
    }
}

void BdptPasses::renderOnlyTiles(std::vector<size_t> tiles) {
    if (tiles.empty()) {
        order_.resize(tiles_.size());
        std::iota(order_.begin(), order_.end(), size_t(0));
    } else {
        order_ = std::move(tiles);
    }
}

LayeredImage BdptPasses::resolve(uint64_t samples, ThreadPool* pool) const {
    return film_.resolve(1.0f / float(samples), ctx_.settings.maxTypeLayers, pool);
}

LayeredImage BdptPasses::takeResolved(uint64_t samples, ThreadPool* pool) {
    return film_.takeResolved(1.0f / float(samples), ctx_.settings.maxTypeLayers, pool);
}

void BdptPasses::keepOddHalf() {
    if (!oddHalf_) oddHalf_.emplace(film_.width(), film_.height(), TypeLayers::of({}));
}

Image BdptPasses::oddHalfSums() const {
    return oddHalf_ ? oddHalf_->resolveCombined(1.0f) : Image(film_.width(), film_.height());
}

Film BdptPasses::film() const {
    Film copy(film_.width(), film_.height(), film_.layers());
    copy.merge(film_);
    return copy;
}

void BdptPasses::addStats(RenderStats& st, double seconds) const {
    st.values["rays"] = double(rays_.load());
    st.values["rays_per_second"] = seconds > 0 ? double(rays_.load()) / seconds : 0;
    st.values["path_types"] = double(film_.typeCount());
    st.values["dropped_samples"] = double(film_.droppedSamples());
}

uint64_t BdptPasses::maxPassSamples() const {
    double pixels = double(film_.width()) * film_.height();
    return uint64_t(std::max(1.0, std::min(1024.0, double(1 << 18) / pixels)));
}

void BdptPasses::renderTile(int x0, int y0, int x1, int y1, SampleRange range, TileSplats& out) {
    out.splats.clear();
    out.sampleStarts.assign(1, 0);
    Scratch scratch;
    Connector connector(ctx_.scene, ctx_.camera);
    // Sample by sample over the tile's pixels, so that the splats come out in sample order.
    for (uint64_t s = range.first; s < range.end; ++s) {
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                Film::Pixel pixel = film_.pixel(x, y);
                std::optional<Film::Pixel> oddPixel;
                if (oddHalf_ && (s & 1)) oddPixel.emplace(oddHalf_->pixel(x, y));
                renderSample(x, y, s, pixel, oddPixel ? &*oddPixel : nullptr, connector, scratch,
                             out.splats);
            }
        out.sampleStarts.push_back(uint32_t(out.splats.size()));
    }
    rays_.fetch_add(scratch.rays, std::memory_order_relaxed);
}

void BdptPasses::renderSample(int x, int y, uint64_t sample, Film::Pixel& pixel,
                              Film::Pixel* oddPixel, Connector& connector, Scratch& scratch,
                              std::vector<Splat>& splats) {
    Rng rng = pixelSampleRng(ctx_.settings.seed, x, y, film_.width(), sample);
    const uint64_t pixelIndex = uint64_t(y) * uint64_t(film_.width()) + uint64_t(x);
    Vec2f u = pixelSamplePosition(ctx_.settings.seed, pixelIndex, sample);
    Ray primary = ctx_.camera.generateRay(filteredRasterPosition(x, y, u));
    traceCameraSubpath(ctx_.scene, ctx_.camera, primary, rng, cameraWalk_, scratch.camera,
                       scratch.rays);
    traceLightSubpath(ctx_.scene, rng, lightWalk_, scratch.light, scratch.rays);
    int cameraCount = int(scratch.camera.size()), lightCount = int(scratch.light.size());
    int maxDepth = ctx_.settings.maxDepth;
    for (int t = 1; t <= cameraCount; ++t)
        for (int s = 0; s <= std::max(lightCount, 1); ++s) {
            if (s + t < 2 || s + t - 2 > maxDepth || !wanted(s, t)) continue;
            // s = 1 with t > 1 samples its own light vertex; every other s needs the subpath.
            if (s > lightCount && !(s == 1 && t > 1)) continue;
            StrategySample c =
                connector.connect(scratch.camera, scratch.light, s, t, rng, scratch.rays,
                                  settings_.weighted, settings_.heuristic);
            if (!c.valid || c.weight <= 0) continue;
            if (key_ && !key_(c.type, sample)) continue;
            Rgb value = c.value * c.weight;
            if (t == 1)
                splats.push_back({c.raster, c.type, value});
            else {
                pixel.add(c.type, value);
                if (oddPixel) oddPixel->add(c.type, value);
            }
        }
}

bool BdptPasses::wanted(int s, int t) const {
    return (settings_.onlyS < 0 || s == settings_.onlyS) &&
           (settings_.onlyT < 0 || t == settings_.onlyT);
}

void BdptPasses::addSplats(SampleRange range, std::span<const size_t> tiles) {
    for (uint64_t i = 0; i < range.count(); ++i) {
        for (size_t t : tiles) {
            const TileSplats& tile = tiles_[t];
            for (uint32_t k = tile.sampleStarts[i]; k < tile.sampleStarts[i + 1]; ++k) {
                const Splat& sp = tile.splats[k];
                splatBuffer_.addTent(sp.raster, sp.type, sp.value);
            }
        }
        const bool odd = oddHalf_ && ((range.first + i) & 1);
        splatBuffer_.flushInto(film_, odd ? &*oddHalf_ : nullptr);
    }
    for (size_t t : tiles) tiles_[t] = TileSplats{};
}

}  // namespace partita
