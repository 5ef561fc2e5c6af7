// The pre-pass of path-space partitioning (paper Sec. 4.2, DESIGN.md "The method, precisely"):
// N start-up samples (mcmc/bootstrap.h) whose every complete path is recorded with its type and
// its MIS-weighted contribution C = w f* / p, split into two halves by sample index:
// - half A (even indices) only sums C per type: gamma(i), the ranking of the types;
// - half B (odd indices) sums C per type (for b_i) and keeps its paths as compact records
//   (sample index, strategy, weight, type, pixel: 40 bytes, regenerated on demand), the
//   candidates of the chains' initial states and the per-partition pre-pass images
//   (partition_images.h), up to a memory budget.
// Keeping the halves apart makes the choice of partitions independent of the estimates of b_i
// and of the initial states.
//
// The estimator is the paper's path tracer (next-event estimation with MIS), which cannot
// sample delta lights seen through specular chains (a point light's caustic); "auto" uses BDPT
// when the scene has a delta light.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "algorithm.h"
#include "clock.h"
#include "mcmc/bootstrap.h"
#include "path_type.h"

namespace partita {

class RenderScene;

/// `setting` is "pt", "bdpt" or "auto"; `why` receives the reason for the choice (for the job's
/// metadata). std::invalid_argument for anything else.
StartupEstimator choosePrepassEstimator(const RenderScene& scene, const std::string& setting,
                                        std::string& why);

struct PrepassResult {
    uint64_t samplesA = 0, samplesB = 0;
    std::map<PathType, double> gamma;  // half A: sum of C per type
    std::map<PathType, double> sumB;   // half B: sum of C per type
    /// half B: per type, the sum over samples of (the sample's C of that type)^2, for the
    /// standard error of b_i (partition.h)
    std::map<PathType, double> sumSquaresB;
    std::vector<BootstrapCandidate> candidatesB;  // half B's paths, in sample order
    bool candidatesTruncated = false;             // the memory budget was reached
    uint64_t rays = 0;
};

/// Runs `samples` samples of `sampler` on ctx's pool in fixed blocks, in waves merged in block
/// order (sample_waves.h: the result does not depend on the thread count, and one wave's
/// per-type tables are alive at a time), reporting progress in the phase "prepass";
/// cancellable. Half B keeps at most `maxCandidateBytes` of records. Past `deadline` no further
/// wave starts: samplesA + samplesB then count the samples that ran (a prefix).
PrepassResult runPrepass(const RenderContext& ctx, const BootstrapSampler& sampler,
                         uint64_t samples, uint64_t maxCandidateBytes = uint64_t(256) << 20,
                         Deadline deadline = kNoDeadline);

}  // namespace partita
