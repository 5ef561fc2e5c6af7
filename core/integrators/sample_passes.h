// The progressive loop every sample-based integrator (pt, bdpt) shares: passes of whole samples
// per pixel, sized so that each ends when the next preview is due, a first preview right after
// the first one-sample pass, a samples-per-pixel or a time budget, cancellation between and
// inside passes, and the progress report. An integrator supplies only what a pass does and how
// its film is resolved (SamplePassRenderer); the loop is here once.
#pragma once

#include <cstdint>

#include "algorithm.h"

namespace partita {

class ProgressReporter;

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
    /// The integrator's own statistics (rays, types, ...); the loop adds spp and timings.
    virtual void addStats(RenderStats& stats, double seconds) const = 0;
    /// The most samples per pixel one pass may take (bounds per-pass buffers).
    virtual uint64_t maxPassSamples() const { return 1024; }
};

/// Runs `renderer` under ctx's budget (samples per pixel or seconds) with previews and progress.
RenderResult runSamplePasses(const RenderContext& ctx, SamplePassRenderer& renderer);

}  // namespace partita
