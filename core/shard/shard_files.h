// The two files of a sharded job (DESIGN.md, "Scale-out"):
// - the plan: the algorithm, the scene (path and a digest of its file), every render setting,
//   the shard count and the algorithm's once-per-job state (Shardable::plan);
// - a shard's result: which plan (its id) and which shard it belongs to, and its work
//   (films, counts, sums), with a checksum so that a truncated or damaged file is refused.
// Both are versioned; reading anything else throws std::invalid_argument with one clear line.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "file_io.h"  // readFileBytes, writeFileAtomic: how these files are read and written
#include "render_settings.h"
#include "shard/shardable.h"

namespace partita {

struct ShardPlan {
    std::string algorithm;
    std::string scene;         // the scene file the plan was made from (as given)
    uint64_t sceneDigest = 0;  // of that file's bytes (shards refuse another scene)
    RenderSettings settings;
    uint32_t shards = 1;
    std::vector<uint8_t> state;  // Shardable::plan's bytes

    /// Identifies the plan: the checksum of its serialised form.
    uint64_t id() const;
};

std::vector<uint8_t> serializeShardPlan(const ShardPlan& plan);
ShardPlan deserializeShardPlan(std::span<const uint8_t> bytes);

struct ShardResult {
    uint64_t planId = 0;
    uint32_t shard = 0, shards = 0;
    ShardWork work;
    uint64_t checksum = 0;  // set by deserializeShardResult: its file's checksum
};

/// `threads`: how many threads write (read) the films' tiles (Film::serializePieces,
/// Film::deserialize); the same bytes
/// for any count.
std::vector<uint8_t> serializeShardResult(const ShardResult& result, int threads = 1);
ShardResult deserializeShardResult(std::span<const uint8_t> bytes, int threads = 1);

/// The checksum a shard result's file ends with: read from the file when it came from one,
/// else computed by serialising it. Equal for equal results (a retried shard).
uint64_t shardResultChecksum(const ShardResult& result);

/// A fast 64-bit checksum of `bytes` (against truncation and damage, not an adversary).
uint64_t fileChecksum(std::span<const uint8_t> bytes);

}  // namespace partita
