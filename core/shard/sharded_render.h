// One job as N shards, front to back (DESIGN.md "Scale-out"; partita-local plan|render|merge
// and partitad's Slurm executor go through here): plan once, render any shard anywhere from
// the plan alone, merge the results in any order (each shard index once), resolve the image.
// The image is bit-identical to runRender's with the same settings, whatever N.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "algorithm.h"
#include "shard/shard_files.h"

namespace partita {

class RenderScene;
class ThreadPool;

/// Everything a shard step needs besides the plan.
struct ShardEnvironment {
    const RenderScene& scene;
    ThreadPool& pool;
    const std::atomic<bool>& cancel;
    RenderObserver& observer;
};

/// Runs the algorithm's once-per-job work and returns the plan of `shards` shards (clamped to
/// what the plan can be split into). std::invalid_argument for an algorithm that cannot be
/// sharded, settings that cannot (a time budget), or shards == 0.
ShardPlan planShardedRender(const ShardEnvironment& env, const std::string& algorithm,
                            const RenderSettings& settings, uint32_t shards,
                            const std::string& scenePath, uint64_t sceneDigest);

/// Renders shard `shard` of the plan (std::invalid_argument when out of range).
ShardResult renderPlannedShard(const ShardEnvironment& env, const ShardPlan& plan, uint32_t shard);

/// Sums shard results of one plan as they arrive, keyed by shard index.
class ShardMerger {
  public:
    explicit ShardMerger(const ShardPlan& plan) : planId_(plan.id()), shards_(plan.shards) {}
    /// Adds a result. Returns false, changing nothing, when that shard was merged already with
    /// the same content (a retried task). std::invalid_argument, changing nothing, for a result
    /// of another plan, another shard count, or a shard index merged with other content.
    bool add(const ShardResult& result);
    /// The same, taking the result's films instead of copying them when it is the first.
    bool add(ShardResult&& result);
    std::vector<uint32_t> missing() const;
    bool complete() const { return merged_.size() == shards_; }
    size_t mergedCount() const { return merged_.size(); }
    const ShardWork& work() const { return work_; }

  private:
    /// Checks `result` against the plan and what is merged (std::invalid_argument); its
    /// checksum, or nothing when that shard was merged already with the same content.
    std::optional<uint64_t> admit(const ShardResult& result) const;
    uint64_t planId_;
    uint32_t shards_;
    std::map<uint32_t, uint64_t> merged_;  // shard index -> checksum of its result
    ShardWork work_;
};

/// The job's image from merged work (complete, or partial for a preview: the scale then counts
/// only the work merged so far).
RenderResult resolveShardedRender(const ShardEnvironment& env, const ShardPlan& plan,
                                  const ShardWork& merged);

}  // namespace partita
