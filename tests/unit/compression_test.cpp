// compression.h: round trips, and damaged or hostile input is refused before anything large is
// allocated.
#include <gtest/gtest.h>

#include <random>

#include "compression.h"

namespace partita {
namespace {

std::vector<uint8_t> varintLikeBytes(size_t n) {
    std::mt19937 rng(4);
    std::geometric_distribution<int> small(0.6);
    std::vector<uint8_t> out(n);
    for (auto& b : out) b = uint8_t(std::min(255, small(rng)));
    return out;
}

/// `bytes` compressed as one piece.
std::vector<uint8_t> compressBytes(const std::vector<uint8_t>& bytes) {
    std::vector<std::vector<uint8_t>> pieces = {bytes};
    std::vector<uint8_t> out;
    appendCompressed(out, pieces);
    return out;
}

TEST(Compression, RoundTripsAndShrinksFilmLikeBytes) {
    const std::vector<uint8_t> bytes = varintLikeBytes(1 << 20);
    const std::vector<uint8_t> packed = compressBytes(bytes);
    EXPECT_LT(packed.size(), bytes.size() / 2);
    EXPECT_EQ(decompressBytes(packed, bytes.size()), bytes);
    EXPECT_EQ(decompressBytes(compressBytes({}), 0), std::vector<uint8_t>{});
}

TEST(Compression, PiecesCompressedOneAfterAnotherAreTheirConcatenation) {
    const std::vector<uint8_t> bytes = varintLikeBytes(300000);
    std::vector<std::vector<uint8_t>> pieces = {{bytes.begin(), bytes.begin() + 7},
                                                {},
                                                {bytes.begin() + 7, bytes.begin() + 200000},
                                                {bytes.begin() + 200000, bytes.end()}};
    std::vector<uint8_t> out = {1, 2, 3};  // appended after what is there
    const size_t appended = appendCompressed(out, pieces);
    ASSERT_EQ(out.size(), 3 + appended);
    EXPECT_EQ(std::vector<uint8_t>(out.begin(), out.begin() + 3), (std::vector<uint8_t>{1, 2, 3}));
    const std::span<const uint8_t> packed(out.data() + 3, appended);
    EXPECT_EQ(decompressBytes(packed, bytes.size()), bytes);
    EXPECT_THROW(decompressBytes(packed, bytes.size() - 1), std::invalid_argument);
    for (const auto& piece : pieces) EXPECT_TRUE(piece.empty()) << "given back";
}

TEST(Compression, RefusesDamageWrongSizesAndImpossibleClaims) {
    const std::vector<uint8_t> bytes = varintLikeBytes(100000);
    std::vector<uint8_t> packed = compressBytes(bytes);
    EXPECT_THROW(decompressBytes(packed, bytes.size() - 1), std::invalid_argument);
    EXPECT_THROW(decompressBytes(packed, bytes.size() + 1), std::invalid_argument);
    std::vector<uint8_t> truncated(packed.begin(), packed.end() - 5);
    EXPECT_THROW(decompressBytes(truncated, bytes.size()), std::invalid_argument);
    packed[packed.size() / 2] ^= 0x5a;
    EXPECT_THROW(decompressBytes(packed, bytes.size()), std::invalid_argument);
    // 40 bytes cannot hold a gigabyte: refused without allocating it.
    EXPECT_THROW(decompressBytes(std::vector<uint8_t>(40, 0), uint64_t(1) << 30),
                 std::invalid_argument);
}

}  // namespace
}  // namespace partita
