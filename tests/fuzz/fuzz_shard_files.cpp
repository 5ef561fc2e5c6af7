// libFuzzer target for the files of a sharded job (core/shard/shard_files.h), which come from a
// shared volume: the first byte picks a plan or a shard result. A result's last 8 bytes are
// replaced by the checksum of the rest, so that mutations reach the body (an adversary can
// write a valid checksum; it guards against damage, not against them). A result that reads
// is merged with itself (ShardWork::add). The contract: bad input throws
// std::invalid_argument; anything else is a bug.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "shard/shard_files.h"

namespace {

void readPlan(const std::vector<uint8_t>& bytes) {
    try {
        partita::ShardPlan plan = partita::deserializeShardPlan(bytes);
        (void)plan.id();
    } catch (const std::invalid_argument&) {
    }
}

void readResult(std::vector<uint8_t> bytes) {
    if (bytes.size() >= 16) {
        const size_t body = bytes.size() - 8;
        const uint64_t sum = partita::fileChecksum(std::span<const uint8_t>(bytes).first(body));
        std::memcpy(bytes.data() + body, &sum, 8);
    }
    try {
        partita::ShardResult result = partita::deserializeShardResult(bytes);
        partita::ShardResult twice = partita::deserializeShardResult(bytes);  // films don't copy
        twice.work.add(result.work);
        (void)partita::shardResultChecksum(result);
    } catch (const std::invalid_argument&) {
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    std::vector<uint8_t> bytes(data + 1, data + size);
    if (data[0] & 1)
        readResult(std::move(bytes));
    else
        readPlan(bytes);
    return 0;
}
