#include "compression.h"

#include <zlib.h>

#include <stdexcept>
#include <string>

namespace partita {

namespace {

/// zlib's largest compression ratio is 1032:1 (a deflate block of one repeated byte).
constexpr uint64_t kMaxRatio = 1032;

}  // namespace

std::vector<uint8_t> compressBytes(std::span<const uint8_t> bytes) {
    uLongf size = compressBound(uLong(bytes.size()));
    std::vector<uint8_t> out(size);
    if (compress2(out.data(), &size, bytes.data(), uLong(bytes.size()), Z_BEST_SPEED) != Z_OK)
        throw std::runtime_error("zlib could not compress " + std::to_string(bytes.size()) +
                                 " bytes");
    out.resize(size);
    return out;
}

std::vector<uint8_t> decompressBytes(std::span<const uint8_t> compressed, uint64_t size) {
    if (size > kMaxRatio * compressed.size() + 64)
        throw std::invalid_argument("compressed data claims " + std::to_string(size) +
                                    " bytes, more than it can hold");
    std::vector<uint8_t> out(size);
    uLongf got = uLongf(size);
    int rc = uncompress(out.data(), &got, compressed.data(), uLong(compressed.size()));
    if (rc != Z_OK || got != size)
        throw std::invalid_argument("damaged compressed data (zlib: " + std::to_string(rc) + ")");
    return out;
}

}  // namespace partita
