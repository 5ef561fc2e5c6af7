#include "shard/shardable.h"

#include <stdexcept>

namespace partita {

void ShardWork::add(const ShardWork& other) {
    if (other.films.size() != films.size() || other.counts.size() != counts.size())
        throw std::invalid_argument("shard work: different film counts");
    for (size_t i = 0; i < films.size(); ++i) films[i].merge(other.films[i]);
    for (size_t i = 0; i < counts.size(); ++i) counts[i] += other.counts[i];
    for (const auto& [name, value] : other.sums) sums[name] += value;
}

ShareRange shareRange(uint64_t total, uint32_t parts, uint32_t part) {
    if (parts == 0 || part >= parts) throw std::invalid_argument("shareRange: bad part");
    uint64_t base = total / parts, extra = total % parts;
    uint64_t first = part * base + std::min<uint64_t>(part, extra);
    return {first, first + base + (part < extra ? 1 : 0)};
}

}  // namespace partita
