// byte_stream.h's varints: every int64 round-trips (the extremes included), small magnitudes
// of either sign take one byte, and a varint past the end or of more than 64 bits is refused.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

#include "byte_stream.h"

namespace partita {
namespace {

TEST(ByteStream, SignedVarintsRoundTripAndRefuseDamage) {
    const std::vector<int64_t> values = {0,
                                         1,
                                         -1,
                                         63,
                                         -64,
                                         64,
                                         1 << 20,
                                         -(1 << 20),
                                         std::numeric_limits<int64_t>::max(),
                                         std::numeric_limits<int64_t>::min()};
    ByteWriter w;
    w.putSignedVarints(values.size(), [&](size_t i) { return values[i]; });
    EXPECT_EQ(w.bytes[0], 0);  // 0, 1, -1: a byte each
    EXPECT_EQ(w.bytes[1], 2);
    EXPECT_EQ(w.bytes[2], 1);
    std::vector<int64_t> back(values.size());
    ByteReader r(w.bytes, "test");
    r.getSignedVarints(values.size(), [&](size_t i, int64_t v) { back[i] = v; });
    EXPECT_EQ(back, values);
    EXPECT_TRUE(r.atEnd());

    std::vector<uint8_t> truncated(w.bytes.begin(), w.bytes.end() - 1);
    ByteReader shortReader(truncated, "test");
    EXPECT_THROW(shortReader.getSignedVarints(values.size(), [](size_t, int64_t) {}),
                 std::invalid_argument);
    const std::vector<uint8_t> tooLong(11, 0x80);  // continues past 64 bits
    ByteReader longReader(tooLong, "test");
    EXPECT_THROW(longReader.getSignedVarints(1, [](size_t, int64_t) {}), std::invalid_argument);
}

}  // namespace
}  // namespace partita
