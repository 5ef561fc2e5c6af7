// How much start-up an MCMC render gets (issue #22 3): the bootstrap's (or pre-pass's) sample
// count and each chain's burn-in follow the job's pixel count and budget instead of fixed
// figures, so that a short budget is not eaten by its start-up.
//
// The rule, written once for mlt, partitioned and guided:
// - Bootstrap samples, when the job leaves "bootstrap" at 0 (the default):
//   - a mutation budget of M = mpp x W x H mutations: N = M * kStartupShare / kSampleCost,
//     within [kMinSamples, kMaxSamples]: the start-up costs about kStartupShare (10%) of the
//     chains' time. kSampleCost is what a BDPT bootstrap sample costs in mutations of time
//     (measured at 256x192 on 2 threads: 8.8-10.7 us a sample against 2.0-2.7 us a mutation on
//     cornell and cornell-glass, 3.3-5.4; in rays a sample is ~22 and a mutation ~2). The
//     bounds: at kMinSamples b (the image's scale) spreads ~2% over seeds (measured on
//     cornell-glass and bathroom, 6 seeds at 4096 samples: 2.0% and 1.9%), far under the
//     per-pixel noise of a budget that small; kMaxSamples is Veach's and Mitsuba's 1e5, the
//     figure every earlier study used (docs/mlt-study.md).
//   - a time budget: kMaxSamples, stopped after "startup_share" of the time (10% by default;
//     startup_parameters.h).
//   A job that sets "bootstrap" gets exactly that.
// - Burn-in steps per chain (partitioned and guided; mlt's chains start from resampled
//   bootstrap paths, Veach's start-up bias elimination, and need none): the pipeline's burn-in,
//   at most kStartupShare of the chain's own mutations with a mutation budget; with a time
//   budget the burn-in stops after kStartupShare of the chains' time (ChainRunner::run).
// Both are in the statistics: bootstrap_samples (prepass_samples) and burn_in (the mean steps
// per chain that ran).
#pragma once

#include <cstdint>

#include "render_settings.h"

namespace partita {

struct StartupRule {
    static constexpr double kStartupShare = 0.1;
    static constexpr double kSampleCost = 5;  // a bootstrap sample, in mutations
    static constexpr uint64_t kMinSamples = 4096;
    static constexpr uint64_t kMaxSamples = 100000;

    /// The bootstrap's samples for a job asking `requested` (0: by the rule above).
    static uint64_t bootstrapSamples(uint64_t requested, const RenderSettings& s);
    /// A chain's burn-in: `burnIn` steps, at most kStartupShare of its `mutations` (a mutation
    /// budget; a time budget plans `burnIn` and the runner stops it at its share of the time).
    static uint64_t burnIn(uint64_t burnIn, uint64_t mutations, const RenderSettings& s);
};

}  // namespace partita
