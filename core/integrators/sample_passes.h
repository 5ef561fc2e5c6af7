// The progressive loop every sample-based integrator (pt, bdpt) shares: passes of whole samples
// per pixel, sized so that each ends when the next preview is due, a first preview right after
// the first one-sample pass, a samples-per-pixel or a time budget, cancellation between and
// inside passes, and the progress report. An integrator supplies only what a pass does and how
// its film is resolved (SamplePassRenderer); the loop is here once.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "algorithm.h"
#include "film.h"
#include "integrators/sample_pass_settings.h"
#include "shard/shardable.h"

namespace partita {

class ProgressReporter;

/// About how long a pass of samples over the whole image runs when no preview is waiting for
/// it. Each pass costs every pixel its film's sums fetched from memory again: at 1280x720,
/// passes of 2 samples per pixel (a second each) rendered 12% slower than passes of 15.
inline constexpr double kPassSecondsWithoutPreviews = 4;

/// Samples [first, end) of every pixel: a pass.
struct SampleRange {
    uint64_t first, end;
    uint64_t count() const { return end - first; }
};

class SamplePassRenderer {
  public:
    virtual ~SamplePassRenderer() = default;
    /// Renders the samples of `range` for every pixel; advances `progress` by pixels x samples.
    /// Results must not depend on how the budget is split into passes.
    virtual void renderPass(SampleRange range, ProgressReporter& progress) = 0;
    /// The image after `samples` samples per pixel; `pool` may be used to resolve it.
    virtual LayeredImage resolve(uint64_t samples, ThreadPool* pool) const = 0;
    /// resolve()'s image at the end of the render, bit for bit; a renderer may consume its film
    /// to make it (Film::takeResolved), so nothing but this is called afterwards.
    virtual LayeredImage takeResolved(uint64_t samples, ThreadPool* pool) {
        return resolve(samples, pool);
    }
    /// The integrator's own statistics (rays, types, ...); the loop adds spp and timings.
    virtual void addStats(RenderStats& stats, double seconds) const = 0;
    /// The most samples per pixel one pass may take (bounds per-pass buffers).
    virtual uint64_t maxPassSamples() const { return 1024; }
    /// From now on, render only the film tiles `tiles` lists (row-major tile indices,
    /// ascending): a pilot that looks at part of the image (partition/effort_pilot.h), paying
    /// for those tiles' time and memory only. Empty: every tile (the default).
    virtual void renderOnlyTiles(std::vector<size_t> tiles) = 0;
    /// From now on, also sum the odd sample indices' contributions apart, in a combined-only
    /// film: the error estimate's half B (half_split_error.h). Called by the sample-pass loop
    /// before its first pass; shards and surveys, which estimate no error, never pay for it.
    virtual void keepOddHalf() = 0;
    /// The film's combined sums so far, unscaled (Film::resolveCombined(1)), and those of its
    /// odd sample indices (after keepOddHalf): the error estimate's input after each pass.
    virtual Image combinedSums() const = 0;
    virtual Image oddHalfSums() const = 0;
    /// A copy of everything rendered so far as one film (resolve(n) is film().resolve(1/n)).
    virtual Film film() const = 0;
    /// film(), moving it out where the renderer keeps it as one (a finished shard's result).
    virtual Film takeFilm() { return film(); }
};

/// Makes an integrator's renderer for ctx, its film keeping `layers` (type_layers.h).
using SamplePassFactory = std::function<std::unique_ptr<SamplePassRenderer>(
    const RenderContext& ctx, const TypeLayers& layers)>;

/// Runs `renderer` under ctx's budget (samples per pixel or seconds) with previews and progress,
/// and the render's own error estimate after each pass (progress value and statistic
/// "error_estimate", the combined image's relative RMSE from two interleaved halves of the
/// passes); with settings.targetError > 0 it stops once the estimate reaches it.
RenderResult runSamplePasses(const RenderContext& ctx, SamplePassRenderer& renderer,
                             const SamplePassSettings& settings = {});

/// A whole render: the type layers from the survey (layer_survey.h), then the renderer the
/// factory makes for them, run by runSamplePasses.
RenderResult renderSamplePasses(const RenderContext& ctx, const SamplePassFactory& factory,
                                const SamplePassSettings& settings = {});

/// The shards of a sample-based integrator: shard i of n renders a contiguous range of sample
/// indices of every pixel (shareRange of the samples per pixel). Every (pixel, sample) has its
/// own random stream and the film sums exactly, so the merged film is the one-process film. The
/// plan is the type layers (chosen once, by the survey).
class SamplePassShards : public Shardable {
  public:
    /// A sharded job renders its whole budget: a target error is refused (plan()).
    explicit SamplePassShards(SamplePassFactory factory, SamplePassSettings settings = {})
        : factory_(std::move(factory)), settings_(settings) {}
    std::vector<uint8_t> plan(const RenderContext& ctx) override;
    ShardWork renderShard(const RenderContext& ctx, std::span<const uint8_t> plan, uint32_t shard,
                          uint32_t shards) override;
    RenderResult resolve(const RenderContext& ctx, std::span<const uint8_t> plan,
                         const ShardWork& merged) override;
    uint32_t maxShards(const RenderContext& ctx, std::span<const uint8_t> plan) const override;

  private:
    SamplePassFactory factory_;
    SamplePassSettings settings_;
};

}  // namespace partita
