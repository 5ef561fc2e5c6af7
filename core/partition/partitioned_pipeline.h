// The pipeline that `partitioned` and `guided` share (paper Sec. 4; DESIGN.md): the pre-pass
// (prepass.h, phase "prepass"), the partitions (partition.h), the partition plan as a chain plan
// with one group per partition (starts resampled from half B, burn-in, seeds: data, so images do
// not depend on the thread count), the chains restricted to their partitions under the job's
// budget with previews (mcmc/chain_render.h), one layer per partition and their sum (Eq. 9), and
// the statistics. What differs between the algorithms is each partition's mutations: a hook
// sees the pre-pass and the partitions (still in the "prepass" phase, cancellable) and returns
// the chains' mutation factory.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "algorithm.h"
#include "mcmc/chain_runner.h"
#include "mcmc/veach_mutations.h"
#include "partition/partition.h"
#include "partition/prepass.h"

namespace partita {

struct PartitionPipelineSettings {
    uint64_t prepassSamples = 100000;  // the same start-up budget as mlt's bootstrap
    uint64_t burnIn = 1024;            // per chain, before its first splat (the paper's)
    int chains = 256;                  // over all partitions, in proportion to P(i)
    uint64_t minMutationsPerChain = 32;
    uint64_t roundMutations = 1024;
    uint64_t prepassMemoryBytes = uint64_t(256) << 20;  // half B's path records
};

/// Given the pre-pass and the partitions, the factory of each partition's (group's) chain
/// mutations; it may add its own statistics to `stats` (they go into the result's).
using PartitionMutationHook = std::function<ChainRunner::MutationFactory(
    const PrepassResult& prepass, const std::vector<Partition>& partitions, RenderStats& stats)>;

/// Veach's mutation settings for the chains of `partition`: those of a one-type partition try
/// only bidirectional mutations that keep the path's length (another length is another type,
/// always rejected); the complement's keep `base`.
VeachMutationSettings partitionMutationSettings(VeachMutationSettings base,
                                                const Partition& partition);

/// Renders ctx's job with the partitioned chains; `algorithm` names it in errors.
RenderResult renderPartitioned(const RenderContext& ctx, const PartitionPipelineSettings& settings,
                               const std::string& algorithm,
                               const PartitionMutationHook& mutations);

}  // namespace partita
