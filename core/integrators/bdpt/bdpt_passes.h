// The passes of bidirectional path tracing (Veach 1997 ch. 10): per pixel sample one camera
// subpath and one light subpath, every strategy (s, t) that joins them (s = 0 emitter hits,
// s = 1 next-event estimation, t = 1 light tracing onto the film), combined with MIS. `bdpt`
// runs them over the whole image; `partitioned` and `guided` run them restricted to the
// partitions they estimate per pixel (partition/per_pixel_partitions.h).
//
// Determinism: every pixel sample draws from its own RNG stream (as pt), so the camera film does
// not depend on threads or passes. Light-tracing splats land anywhere, so each tile records its
// splats in sample order and they are added after the pass in (sample, tile) order: the image
// is bit-identical for any thread count and any split of the budget into passes.
#pragma once

#include <atomic>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "algorithm.h"
#include "film.h"
#include "integrators/bdpt/bdpt_settings.h"
#include "integrators/contribution_key.h"
#include "integrators/sample_passes.h"
#include "path/random_walk.h"
#include "splat_buffer.h"

namespace partita {

class Connector;

class BdptPasses : public SamplePassRenderer {
  public:
    BdptPasses(const RenderContext& ctx, const BdptSettings& settings, const TypeLayers& layers,
               ContributionKey key = {});

    /// The pass in batches of kBatchTiles tiles (fixed by the tile index, not by the threads):
    /// each batch's tiles in parallel, then its light-tracing splats into the film. The splats
    /// held at once are a batch's, not the whole image's (at 1080p a pass of one sample per
    /// pixel left ~1 GB of them).
    void renderPass(SampleRange range, ProgressReporter& progress) override;
    LayeredImage resolve(uint64_t samples, ThreadPool* pool) const override;
    LayeredImage takeResolved(uint64_t samples, ThreadPool* pool) override;
    void keepOddHalf() override;
    Image combinedSums() const override { return film_.resolveCombined(1.0f); }
    Image oddHalfSums() const override;
    Film film() const override;
    Film takeFilm() override { return std::move(film_); }
    void addStats(RenderStats& st, double seconds) const override;
    /// Splats are held for a batch of a pass: keep a pass to about 2^18 pixel samples.
    uint64_t maxPassSamples() const override;
    void renderOnlyTiles(std::vector<size_t> tiles) override;
    uint64_t rays() const { return rays_.load(); }

  private:
    static constexpr size_t kBatchTiles = 256;  // 65536 pixels

    /// A light-tracing contribution waiting to be added to the film.
    struct Splat {
        Vec2f raster;
        PathType type;
        Rgb value;
    };
    /// One tile's splats of a pass, sample by sample: sampleStarts[i] .. sampleStarts[i+1]
    /// index those of the pass's i-th sample.
    struct TileSplats {
        std::vector<Splat> splats;
        std::vector<uint32_t> sampleStarts;
    };
    /// Per-thread scratch of one pixel sample.
    struct Scratch {
        std::vector<PathVertex> camera, light;
        uint64_t rays = 0;
    };

    void renderTile(int x0, int y0, int x1, int y1, SampleRange range, TileSplats& out);
    /// `oddPixel`: the pixel in the odd half's film for an odd sample (keepOddHalf), else null.
    void renderSample(int x, int y, uint64_t sample, Film::Pixel& pixel, Film::Pixel* oddPixel,
                      Connector& connector, Scratch& scratch, std::vector<Splat>& splats);
    bool wanted(int s, int t) const;
    /// The splats of `tiles` (one batch), sample by sample and within a sample tile by tile:
    /// the same order whatever the threads did and however the budget was split into passes.
    /// A group per sample index and batch (splat_buffer.h: accurate float sums). The tiles'
    /// lists are emptied (their memory given back).
    void addSplats(SampleRange range, std::span<const size_t> tiles);

    const RenderContext& ctx_;
    BdptSettings settings_;
    ContributionKey key_;
    WalkSettings cameraWalk_, lightWalk_;
    // Camera-side samples (per tile, from the pass's threads) and light-tracing splats (after
    // the pass, serially) go into the one film: its sums are exact, so the order is immaterial.
    Film film_;
    std::optional<Film> oddHalf_;  // the odd sample indices' combined sums (keepOddHalf)
    SplatBuffer splatBuffer_;
    std::vector<TileSplats> tiles_;
    std::vector<size_t> order_;  // the tiles a pass renders, ascending (renderOnlyTiles)
    std::atomic<uint64_t> rays_{0};
};

}  // namespace partita
