// What an algorithm implements to run one job as N shards in separate processes (DESIGN.md,
// "Scale-out"): plan() does the once-per-job work (mlt's bootstrap and chain plan; nothing for
// pt/bdpt) and returns it as bytes; renderShard() renders shard i of n from those bytes alone;
// resolve() turns the merged work of all shards into the job's image. Films sum exactly
// (film.h), so the image of the merged shards is bit-identical to render() with the same
// settings, for any n and any order of merging.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "algorithm.h"
#include "film.h"
#include "share_range.h"

namespace partita {

/// What shards produce and what merges: films (one per chain group; pt/bdpt have one), the
/// work done per film (samples per pixel, or mutations), and additive statistics (rays, ...).
struct ShardWork {
    std::vector<Film> films;
    std::vector<uint64_t> counts;
    std::map<std::string, double> sums;

    /// Adds `other` (same film count and sizes, else std::invalid_argument). Films and counts
    /// add exactly; sums are doubles added in the order merges happen.
    void add(const ShardWork& other);
};

class Shardable {
  public:
    virtual ~Shardable() = default;
    /// The once-per-job work, as bytes every shard gets.
    virtual std::vector<uint8_t> plan(const RenderContext& ctx) = 0;
    /// Shard `shard` of `shards` (0 <= shard < shards).
    virtual ShardWork renderShard(const RenderContext& ctx, std::span<const uint8_t> plan,
                                  uint32_t shard, uint32_t shards) = 0;
    /// The job's image from the sum of every shard's work.
    virtual RenderResult resolve(const RenderContext& ctx, std::span<const uint8_t> plan,
                                 const ShardWork& merged) = 0;
    /// The most shards the plan can be split into (a shard needs at least one chain or sample).
    virtual uint32_t maxShards(const RenderContext& ctx, std::span<const uint8_t> plan) const = 0;
};

}  // namespace partita
