// Lossless compression of the bytes a job writes to shared volumes (shard results: their films
// are varints), with Zstandard (Debian's libzstd) at its fastest standard level: it compresses
// at several hundred MB/s and decompresses near 1 GB/s, so a shard's file costs its writer and
// the merge little more than the bytes' copy (zlib's deflate cost seconds per 100 MB on both
// sides for the same ratio: docs/shard-overhead.md).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace partita {

/// The pieces' concatenation compressed (one frame), appended to `out` without making that
/// concatenation; each piece is emptied (its memory given back) once it is consumed. Returns
/// the number of bytes appended.
size_t appendCompressed(std::vector<uint8_t>& out, std::vector<std::vector<uint8_t>>& pieces);

/// The `size` bytes `compressed` holds; std::invalid_argument when it is not one Zstandard frame
/// of exactly that many bytes, or `size` is more than such a frame could have compressed into
/// it (so a hostile file cannot make it allocate more than ~33000 times its own size).
std::vector<uint8_t> decompressBytes(std::span<const uint8_t> compressed, uint64_t size);

}  // namespace partita
