// The settings of `partitioned` with their defaults (paper Sec. 4; DESIGN.md). K, the pre-pass
// estimator and the pre-pass size come from the job (RenderSettings: partitions, prepass,
// bootstrapSamples).
#pragma once

#include <cstdint>

#include "mcmc/veach_mutations.h"

namespace partita {

struct PartitionedSettings {
    uint64_t prepassSamples = 100000;  // the same start-up budget as mlt's bootstrap
    uint64_t burnIn = 1024;            // per chain, before its first splat (the paper's)
    int chains = 256;                  // over all partitions, in proportion to P(i)
    uint64_t minMutationsPerChain = 32;
    uint64_t roundMutations = 1024;
    uint64_t prepassMemoryBytes = uint64_t(256) << 20;  // half B's path records
    /// Veach's mutations, unchanged. Chains of a one-type partition try only bidirectional
    /// mutations that keep the path's length (a different length is another type).
    VeachMutationSettings mutations;
};

}  // namespace partita
