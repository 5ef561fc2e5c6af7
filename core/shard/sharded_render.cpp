#include "shard/sharded_render.h"

#include <memory>
#include <optional>
#include <stdexcept>

#include "camera.h"
#include "render_scene.h"
#include "renderer.h"
#include "shard/shardable.h"

namespace partita {

namespace {

/// The algorithm of a plan, its Shardable, and the render context of the plan's settings.
class ShardJob {
  public:
    ShardJob(const ShardEnvironment& env, const std::string& algorithm,
             const RenderSettings& settings)
        : prepared_(prepareRender(env.scene, algorithm, settings)),
          ctx_{env.scene, prepared_.camera, settings, env.pool, env.cancel, env.observer},
          shardable_(prepared_.algorithm->shardable()) {
        if (!shardable_)
            throw std::invalid_argument("algorithm '" + algorithm + "' cannot run as shards");
    }
    const RenderContext& ctx() const { return ctx_; }
    Shardable& shards() { return *shardable_; }

  private:
    PreparedRender prepared_;
    RenderContext ctx_;
    Shardable* shardable_;
};

}  // namespace

ShardPlan planShardedRender(const ShardEnvironment& env, const std::string& algorithm,
                            const RenderSettings& settings, uint32_t shards,
                            const std::string& scenePath, uint64_t sceneDigest) {
    if (shards == 0) throw std::invalid_argument("a plan needs at least one shard");
    ShardJob job(env, algorithm, settings);
    ShardPlan plan;
    plan.algorithm = algorithm;
    plan.scene = scenePath;
    plan.sceneDigest = sceneDigest;
    plan.settings = settings;
    plan.state = job.shards().plan(job.ctx());
    plan.shards = std::min(shards, job.shards().maxShards(job.ctx(), plan.state));
    return plan;
}

ShardResult renderPlannedShard(const ShardEnvironment& env, const ShardPlan& plan, uint32_t shard) {
    if (shard >= plan.shards)
        throw std::invalid_argument(
            "shard " + std::to_string(shard) + " is out of range: the plan has " +
            std::to_string(plan.shards) + " shards (0.." + std::to_string(plan.shards - 1) + ")");
    ShardJob job(env, plan.algorithm, plan.settings);
    ShardResult result;
    result.planId = plan.id();
    result.shard = shard;
    result.shards = plan.shards;
    result.work = job.shards().renderShard(job.ctx(), plan.state, shard, plan.shards);
    return result;
}

std::optional<uint64_t> ShardMerger::admit(const ShardResult& result) const {
    if (result.planId != planId_)
        throw std::invalid_argument("shard " + std::to_string(result.shard) +
                                    " belongs to another plan (another job or plan version)");
    if (result.shards != shards_ || result.shard >= shards_)
        throw std::invalid_argument("shard " + std::to_string(result.shard) + " of " +
                                    std::to_string(result.shards) + " does not match the plan's " +
                                    std::to_string(shards_) + " shards");
    // With the plan and the index equal, the checksum of the result tells a retried task (the
    // same bits) from a clash.
    const uint64_t digest = shardResultChecksum(result);
    if (auto it = merged_.find(result.shard); it != merged_.end()) {
        if (it->second == digest) return std::nullopt;
        throw std::invalid_argument("shard " + std::to_string(result.shard) +
                                    " was merged already with different content");
    }
    return digest;
}

bool ShardMerger::add(const ShardResult& result) {
    const std::optional<uint64_t> digest = admit(result);
    if (!digest) return false;
    if (merged_.empty()) {
        work_.films.clear();
        for (const Film& f : result.work.films)
            work_.films.emplace_back(f.width(), f.height(), f.layers());
        work_.counts.assign(result.work.counts.size(), 0);
        work_.sums.clear();
    }
    work_.add(result.work);
    merged_[result.shard] = *digest;
    return true;
}

bool ShardMerger::add(ShardResult&& result) {
    if (!merged_.empty()) return add(static_cast<const ShardResult&>(result));
    const std::optional<uint64_t> digest = admit(result);  // nothing merged: never a duplicate
    work_ = std::move(result.work);
    merged_[result.shard] = *digest;
    return true;
}

std::vector<uint32_t> ShardMerger::missing() const {
    std::vector<uint32_t> out;
    for (uint32_t i = 0; i < shards_; ++i)
        if (!merged_.count(i)) out.push_back(i);
    return out;
}

RenderResult resolveShardedRender(const ShardEnvironment& env, const ShardPlan& plan,
                                  const ShardWork& merged) {
    ShardJob job(env, plan.algorithm, plan.settings);
    if (merged.films.empty()) throw std::invalid_argument("nothing merged yet");
    return job.shards().resolve(job.ctx(), plan.state, merged);
}

}  // namespace partita
