// The settings of `guided` with their defaults (paper Sec. 5; DESIGN.md). K, |Y'|, R, epsilon,
// the pre-pass estimator and size come from the job (RenderSettings: partitions,
// guideCandidates, guideRadius, guideEpsilon, prepass, bootstrapSamples).
#pragma once

#include "guide/denoise.h"
#include "mcmc/veach_mutations.h"
#include "partition/partitioned_pipeline.h"

namespace partita {

struct GuidedSettings : PartitionPipelineSettings {
    /// Veach's mutations as in `partitioned`, the guided image perturbation in the lens
    /// perturbation's place (with its weight).
    VeachMutationSettings mutations;
    /// The per-partition denoiser of the pre-pass images that V' thresholds (Eq. 17).
    DenoiseSettings denoise;
};

}  // namespace partita
