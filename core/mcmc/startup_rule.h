// How much start-up an MCMC render gets (issue #22 3): the bootstrap's (or pre-pass's) sample
// count and each chain's burn-in follow the job's pixel count and budget instead of fixed
// figures, so that a short budget is not eaten by its start-up.
//
// The rule, written once for mlt, partitioned and guided:
// - Bootstrap samples, when the job leaves "bootstrap" at 0 (the default):
//   - a mutation budget of M = mpp x W x H mutations: N = M / kSampleCost within
//     [kMinSamples, kMaxSamples]: the bootstrap costs at most about what the chains cost.
//     kSampleCost is what a BDPT bootstrap sample costs in mutations of time (measured at
//     256x192 on 2 threads: 8.8-10.7 us a sample against 2.0-2.7 us a mutation on cornell and
//     cornell-glass, 3.3-5.4; in rays a sample is ~22 and a mutation ~2).
//     Why not less: the bootstrap's b is the image's scale, and its error does not fall with
//     the mutations. On cornell-glass at 256x192, 8 seeds each (docs/startup-rule.md), a tenth
//     of the chains' time (15729 samples at 16 mpp) gave 1.45x the MSE x time of the fixed
//     1e5 for mlt and 1.8x for partitioned, while N = M / 5 (39321 samples at 4 mpp) gave
//     0.70x and 0.59x of the fixed 1e5's MSE x time (the same RMSE within its spread, in 67% and
//     53% of the time). At 16 mpp and more the rule gives the fixed 1e5 again.
//     The bounds: at kMinSamples b spreads ~2% over seeds (cornell-glass and bathroom, 6 seeds
//     at 4096 samples); kMaxSamples is Veach's and Mitsuba's 1e5 (and bounds the candidates'
//     memory: ~53 MiB).
//   - a time budget: kMaxSamples, stopped after "startup_share" of the time (10% by default;
//     startup_parameters.h).
//   A job that sets "bootstrap" gets exactly that.
// - Burn-in steps per chain (partitioned and guided, parameter "burn_in"; mlt's chains start
//   from resampled bootstrap paths, Veach's start-up bias elimination, and run none): at most
//   kBurnInShare of the chain's own mutations with a mutation budget; with a time budget the
//   burn-in stops after kBurnInShare of the chains' time (ChainRunner::run). Measured on
//   cornell-glass at 256x192, 16 mpp, 8 seeds: partitioned's RMSE 0.1328 with 307 steps a chain
//   and 0.1348 with none (within its spread, 0.041), 2.80 and 2.43 s.
// Both are in the statistics: bootstrap_samples (prepass_samples) and burn_in (the mean steps
// per chain that ran).
#pragma once

#include <cstdint>

#include "render_settings.h"

namespace partita {

struct StartupRule {
    static constexpr double kBurnInShare = 0.1;
    static constexpr double kSampleCost = 5;  // a bootstrap sample, in mutations
    static constexpr uint64_t kMinSamples = 4096;
    static constexpr uint64_t kMaxSamples = 100000;

    /// The bootstrap's samples for a job asking `requested` (0: by the rule above).
    static uint64_t bootstrapSamples(uint64_t requested, const RenderSettings& s);
    /// A chain's burn-in: `burnIn` steps, at most kBurnInShare of its `mutations` (a mutation
    /// budget; a time budget plans `burnIn` and the runner stops it at its share of the time).
    static uint64_t burnIn(uint64_t burnIn, uint64_t mutations, const RenderSettings& s);
};

}  // namespace partita
