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

}  // namespace partita
