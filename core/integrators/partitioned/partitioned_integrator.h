// Path-space partitioning as an Algorithm ("partitioned", paper Sec. 4): a pre-pass
// (partition/prepass.h) ranks the path types, the top K and their complement become partitions
// (partition/partition.h), and each partition is integrated by its own chains of Veach's
// mutations restricted to it, with its own normalising constant b_i; mutations go to the
// partitions in proportion to P(i) (Eq. 10) and the image is the sum of the partitions' images
// (Eq. 9). The partition plan (types, gamma, P(i), b_i, starts, seeds) is a chain plan with one
// group per partition (mcmc/chain_plan.h), so images do not depend on the thread count.
//
// The result has the combined image and one layer per partition, named by its type string (the
// complement "complement"). K = 0 leaves the complement alone: mlt with a pre-pass.
#pragma once

#include "algorithm.h"
#include "integrators/partitioned/partitioned_settings.h"
#include "partition/partitioned_pipeline.h"

namespace partita {

/// partitioned's mutations: Veach's, a one-type partition's keeping the path's length.
class VeachPartitionMutations : public PartitionMutations {
  public:
    explicit VeachPartitionMutations(const VeachMutationSettings& settings) : settings_(settings) {}
    ChainRunner::MutationFactory factory(const RenderContext& ctx,
                                         const std::vector<Partition>& partitions,
                                         std::span<const uint8_t> prepared) override;

  private:
    VeachMutationSettings settings_;
};

class PartitionedAlgorithm : public Algorithm {
  public:
    explicit PartitionedAlgorithm(PartitionedSettings settings = {});
    ~PartitionedAlgorithm() override;
    RenderResult render(const RenderContext& ctx) override;
    Shardable* shardable() override { return &shards_; }

  private:
    PartitionedSettings settings_;
    VeachPartitionMutations mutations_;
    PartitionedShards shards_;
};

void registerPartitioned();

}  // namespace partita
