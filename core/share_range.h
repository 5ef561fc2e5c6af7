// `total` items split into `parts` contiguous ranges as evenly as possible: the first
// total % parts ranges get one item more. Mutations over a plan's chains, sample indices or
// chains over shards.
#pragma once

#include <algorithm>
#include <cstdint>
#include <stdexcept>

namespace partita {

struct ShareRange {
    uint64_t first, end;
    uint64_t count() const { return end - first; }
};

/// Range `part` (0 <= part < parts; std::invalid_argument otherwise).
inline ShareRange shareRange(uint64_t total, uint64_t parts, uint64_t part) {
    if (parts == 0 || part >= parts) throw std::invalid_argument("shareRange: bad part");
    const uint64_t base = total / parts, extra = total % parts;
    const uint64_t first = part * base + std::min(part, extra);
    return {first, first + base + (part < extra ? 1 : 0)};
}

}  // namespace partita
