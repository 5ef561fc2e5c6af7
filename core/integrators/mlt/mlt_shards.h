// mlt as shards (shard/shardable.h): the plan is the bootstrap's chain plan (b, every chain's
// start, stream and mutations) and its rays; shard i runs a range of the chains; the merged
// film resolves with b W H / N exactly as the one-process render does.
#pragma once

#include "integrators/mlt/mlt_settings.h"
#include "shard/shardable.h"

namespace partita {

class MltShards : public Shardable {
  public:
    explicit MltShards(MltSettings settings) : settings_(std::move(settings)) {}
    std::vector<uint8_t> plan(const RenderContext& ctx) override;
    ShardWork renderShard(const RenderContext& ctx, std::span<const uint8_t> plan, uint32_t shard,
                          uint32_t shards) override;
    RenderResult resolve(const RenderContext& ctx, std::span<const uint8_t> plan,
                         const ShardWork& merged) override;
    uint32_t maxShards(const RenderContext& ctx, std::span<const uint8_t> plan) const override;

  private:
    MltSettings settings_;
};

}  // namespace partita
