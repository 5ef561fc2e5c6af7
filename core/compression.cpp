#include "compression.h"

#include <zstd.h>

#include <memory>
#include <new>
#include <stdexcept>
#include <string>

namespace partita {

namespace {

/// Level 1: Zstandard's fastest standard level. Film varints gain only ~2% more at level 3.
constexpr int kLevel = 1;

/// The largest ratio a Zstandard frame reaches: an RLE block (a 3-byte header and the byte)
/// stands for at most 128 KiB, 32768:1; the frame header and checksum are below the slack.
constexpr uint64_t kMaxRatio = (uint64_t(128) << 10) / 4;

using Context = std::unique_ptr<ZSTD_CCtx, size_t (*)(ZSTD_CCtx*)>;

/// A compression context of kLevel whose frames carry their checksum (xxHash64, cheap): a
/// damaged frame fails to decompress instead of decoding into other bytes of the same size.
Context newContext() {
    Context context(ZSTD_createCCtx(), ZSTD_freeCCtx);
    if (!context) throw std::bad_alloc();
    ZSTD_CCtx_setParameter(context.get(), ZSTD_c_compressionLevel, kLevel);
    ZSTD_CCtx_setParameter(context.get(), ZSTD_c_checksumFlag, 1);
    return context;
}

void check(size_t result, size_t inputBytes) {
    if (ZSTD_isError(result))
        throw std::runtime_error("zstd could not compress " + std::to_string(inputBytes) +
                                 " bytes: " + ZSTD_getErrorName(result));
}

}  // namespace

size_t appendCompressed(std::vector<uint8_t>& out, std::vector<std::vector<uint8_t>>& pieces) {
    size_t total = 0;
    for (const auto& p : pieces) total += p.size();
    Context context = newContext();
    check(ZSTD_CCtx_setPledgedSrcSize(context.get(), total), total);  // the frame states it
    const size_t start = out.size();
    out.resize(start + ZSTD_compressBound(total));
    ZSTD_outBuffer output{out.data(), out.size(), start};
    for (auto& piece : pieces) {
        ZSTD_inBuffer input{piece.data(), piece.size(), 0};
        while (input.pos < input.size)
            check(ZSTD_compressStream2(context.get(), &output, &input, ZSTD_e_continue), total);
        std::vector<uint8_t>().swap(piece);
    }
    ZSTD_inBuffer none{nullptr, 0, 0};
    size_t left = 0;
    do {
        left = ZSTD_compressStream2(context.get(), &output, &none, ZSTD_e_end);
        check(left, total);
    } while (left != 0);
    out.resize(output.pos);
    return output.pos - start;
}

std::vector<uint8_t> decompressBytes(std::span<const uint8_t> compressed, uint64_t size) {
    if (size > kMaxRatio * compressed.size() + 64)
        throw std::invalid_argument("compressed data claims " + std::to_string(size) +
                                    " bytes, more than it can hold");
    // The frame states its size: checked before the output is allocated.
    const unsigned long long stated =
        ZSTD_getFrameContentSize(compressed.data(), compressed.size());
    if (stated != size)
        throw std::invalid_argument("damaged compressed data (its frame does not hold " +
                                    std::to_string(size) + " bytes)");
    std::vector<uint8_t> out(size);
    const size_t got =
        ZSTD_decompress(out.data(), out.size(), compressed.data(), compressed.size());
    if (ZSTD_isError(got) || got != size)
        throw std::invalid_argument(std::string("damaged compressed data (zstd: ") +
                                    (ZSTD_isError(got) ? ZSTD_getErrorName(got) : "short") + ")");
    return out;
}

}  // namespace partita
