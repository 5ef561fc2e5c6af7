// The reference path tracer as an Algorithm ("pt"): progressive passes over tiles, one RNG
// stream per (pixel, sample), so the image is bit-identical for any thread count and any split
// of the budget into passes.
#pragma once

#include <cstdint>
#include <memory>

#include "algorithm.h"
#include "integrators/contribution_key.h"
#include "integrators/sample_pass_settings.h"
#include "math/vec.h"
#include "rng.h"

namespace partita {

class Film;

/// Raster position of sample `u` in pixel (x, y): the pixel centre offset by a tent filter of
/// radius one pixel, sampled exactly (filter importance sampling), so every sample belongs to
/// one pixel with weight 1.
Vec2f filteredRasterPosition(int x, int y, Vec2f u);

/// The RNG for sample `sampleIndex` of pixel (x, y) of a `width`-wide image under `seed`.
inline Rng pixelSampleRng(uint64_t seed, int x, int y, int width, uint64_t sampleIndex) {
    uint64_t pixel = uint64_t(y) * uint64_t(width) + uint64_t(x);
    return Rng(seed, pixelSampleStream(pixel, sampleIndex));
}

class SamplePassRenderer;
class TypeLayers;

/// The path tracer's passes over a film keeping `layers`, only the contributions `key` keeps
/// (integrators/contribution_key.h): the per-pixel partitions' estimator.
std::unique_ptr<SamplePassRenderer> makeRestrictedPathTracerPasses(const RenderContext& ctx,
                                                                   const TypeLayers& layers,
                                                                   ContributionKey key);

class PathTracerAlgorithm : public Algorithm {
  public:
    explicit PathTracerAlgorithm(SamplePassSettings settings = {});
    ~PathTracerAlgorithm() override;
    RenderResult render(const RenderContext& ctx) override;
    Shardable* shardable() override;

  private:
    SamplePassSettings settings_;
    std::unique_ptr<Shardable> shards_;
};

void registerPathTracer();

}  // namespace partita
