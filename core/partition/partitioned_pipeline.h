// The pipeline that `partitioned` and `guided` share (paper Sec. 4; DESIGN.md): the pre-pass
// (prepass.h, phase "prepass"), the partitions (partition.h), the partition plan as a chain plan
// with one group per partition (starts resampled from half B, burn-in, seeds: data, so images do
// not depend on the thread count), the chains restricted to their partitions under the job's
// budget with previews (mcmc/chain_render.h), one layer per partition and their sum (Eq. 9), and
// the statistics. What differs between the algorithms is each partition's mutations
// (PartitionMutations): after the pre-pass and the partitions (still in the "prepass" phase,
// cancellable) it prepares what its mutations read, as bytes a shard plan can carry, and makes
// the chains' mutation factory from them. PartitionedShards runs the same pipeline as shards.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "algorithm.h"
#include "mcmc/chain_runner.h"
#include "mcmc/veach_mutations.h"
#include "partition/partition.h"
#include "partition/pipeline_settings.h"
#include "partition/prepass.h"
#include "shard/shardable.h"

namespace partita {

/// Each partition's (group's) chain mutations, for one algorithm.
class PartitionMutations {
  public:
    virtual ~PartitionMutations() = default;
    /// Runs once, after the pre-pass and the partitions: what the mutations read beyond the
    /// partitions, as bytes (guided: its support masks); it may add statistics to `stats`.
    virtual std::vector<uint8_t> prepare(const RenderContext&, const PrepassResult&,
                                         const std::vector<Partition>&, RenderStats&) {
        return {};
    }
    /// The mutation factory of the chains, from the partitions and prepare's bytes (in this
    /// process or in a shard's); the same bytes must give the same mutations. Partition g's
    /// chains use the move moves()[partitions[g].move].
    virtual ChainRunner::MutationFactory factory(const RenderContext& ctx,
                                                 const std::vector<Partition>& partitions,
                                                 std::span<const uint8_t> prepared) = 0;
    /// The image-plane moves the chains' pilot chooses from per partition (the one of lower
    /// measured error per cost; the first on a tie or without a pilot), by name for the
    /// statistics. One (or none): nothing to choose.
    virtual std::vector<std::string> moves() const { return {}; }
};

/// Veach's mutation settings for the chains of `partition`: those of a one-type partition try
/// only bidirectional mutations that keep the path's length (another length is another type,
/// always rejected), and independence proposals of that length only; the complement's keep
/// `base`.
VeachMutationSettings partitionMutationSettings(VeachMutationSettings base,
                                                const Partition& partition);

/// Renders ctx's job with the partitioned chains; `algorithm` names it in errors.
RenderResult renderPartitioned(const RenderContext& ctx, const PartitionPipelineSettings& settings,
                               const std::string& algorithm, PartitionMutations& mutations);

/// The pipeline as shards (shard/shardable.h): the plan is the pre-pass's outcome (partitions,
/// b_i, P(i), the chain plan, prepare's bytes, the start-up statistics); shard i runs a range
/// of the chains; the merged films resolve as the one-process render's.
class PartitionedShards : public Shardable {
  public:
    PartitionedShards(const PartitionPipelineSettings& settings, std::string algorithm,
                      PartitionMutations& mutations)
        : settings_(settings), algorithm_(std::move(algorithm)), mutations_(mutations) {}
    std::vector<uint8_t> plan(const RenderContext& ctx) override;
    ShardWork renderShard(const RenderContext& ctx, std::span<const uint8_t> plan, uint32_t shard,
                          uint32_t shards) override;
    RenderResult resolve(const RenderContext& ctx, std::span<const uint8_t> plan,
                         const ShardWork& merged) override;
    uint32_t maxShards(const RenderContext& ctx, std::span<const uint8_t> plan) const override;

  private:
    const PartitionPipelineSettings& settings_;
    std::string algorithm_;
    PartitionMutations& mutations_;
};

}  // namespace partita
