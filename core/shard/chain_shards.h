// What the MCMC algorithms share to run as shards: shard i of n runs a contiguous range of the
// chain plan's chains (every chain's result depends only on its own entry in the plan,
// chain_plan.h), and hands back its groups' films, the mutations done in each group, the rays
// and the per-mutation counts.
#pragma once

#include <cstdint>
#include <string>

#include "mcmc/chain_plan.h"
#include "mcmc/chain_runner.h"
#include "shard/shardable.h"

namespace partita {

struct RenderStats;

/// The plan restricted to shard `shard` of `shards` (groups unchanged, a range of chains).
ChainPlan chainShardPlan(const ChainPlan& plan, uint32_t shard, uint32_t shards);

/// std::invalid_argument unless ctx's budget is mutations per pixel (a time budget is not
/// reproducible across machines).
void requireMutationBudget(const RenderContext& ctx, const std::string& algorithm);

/// Runs shard `shard` of `shards` of `plan` (its range of chains) to the end and returns its
/// work: one film (laid out as `layout`) and one mutation count per group, "rays", "proposed_<m>"
/// and "accepted_<m>" per mutation, "group_<g>_proposed" and "group_<g>_accepted" per group.
ShardWork runChainShard(const RenderContext& ctx, const ChainPlan& plan, uint32_t shard,
                        uint32_t shards, const ChainRunner::MutationFactory& mutations,
                        const ChainRunner::RestrictionFactory& restrictions,
                        uint64_t roundMutations,
                        ChainRunner::FilmLayout layout = ChainRunner::FilmLayout::PerGroup);

/// The statistics of merged chain work, as addChainStats gives them in process (without the
/// timings, which a merge does not know).
void addMergedChainStats(RenderStats& stats, const ShardWork& merged, const ChainPlan& plan,
                         double pixels);

}  // namespace partita
