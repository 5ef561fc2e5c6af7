// The settings of `partitioned` with their defaults (paper Sec. 4; DESIGN.md). K, the pre-pass
// estimator and the pre-pass size come from the job (RenderSettings: partitions, prepass,
// bootstrapSamples).
#pragma once

#include "mcmc/veach_mutations.h"
#include "partition/partitioned_pipeline.h"

namespace partita {

struct PartitionedSettings : PartitionPipelineSettings {
    /// Veach's mutations, unchanged. Chains of a one-type partition try only bidirectional
    /// mutations that keep the path's length (a different length is another type).
    VeachMutationSettings mutations;
};

}  // namespace partita
