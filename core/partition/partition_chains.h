// The chains of the partitions as a chain plan (mcmc/chain_plan.h): group g is partition g; its
// chains (in proportion to its mutations, at least one, none for a partition without mutations)
// start from half B's paths of the partition, resampled in proportion to their contributions.
// Starts, seeds and burn-in are data, so images do not depend on the thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "algorithm.h"
#include "mcmc/chain_plan.h"
#include "partition/partition.h"
#include "partition/pipeline_settings.h"
#include "partition/prepass.h"

namespace partita {

class BootstrapSampler;

/// `salt` 0 gives the render's chains; another value independent ones (the pilot's,
/// effort_pilot.h): other resampled starts and other random streams.
ChainPlan planPartitionChains(const RenderContext& ctx, const BootstrapSampler& sampler,
                              const PrepassResult& prepass,
                              const std::vector<Partition>& partitions,
                              const std::vector<uint64_t>& mutations,
                              const PartitionPipelineSettings& s, uint64_t salt = 0);

}  // namespace partita
