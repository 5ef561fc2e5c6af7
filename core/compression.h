// Lossless compression of the bytes a job writes to shared volumes (shard results: their films
// are mostly small varints), with zlib (Debian's zlib1g), at its fastest level.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace partita {

std::vector<uint8_t> compressBytes(std::span<const uint8_t> bytes);

/// The `size` bytes `compressed` holds; std::invalid_argument when it is not a zlib stream of
/// exactly that many bytes, or `size` is more than zlib could have compressed into it (so a
/// hostile file cannot make it allocate more than ~1000 times its own size).
std::vector<uint8_t> decompressBytes(std::span<const uint8_t> compressed, uint64_t size);

}  // namespace partita
