#include "pixel_sample_position.h"

#include "rng.h"

namespace partita {

namespace {

/// The stream of a pixel's scramble for the sample indices of one parity: no sample's own
/// stream (pixelSampleStream(pixel, s) with s below 2^63).
constexpr uint64_t kScrambleStream = ~uint64_t(0) - 0x5c0b01;

}  // namespace

Vec2f scrambledSobol02(uint32_t n, uint32_t scrambleX, uint32_t scrambleY) {
    uint32_t x = n;  // van der Corput: the bits of n reversed
    x = (x << 16) | (x >> 16);
    x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
    x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
    x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
    x = ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
    x ^= scrambleX;
    uint32_t y = scrambleY;
    for (uint32_t v = 1u << 31; n != 0; n >>= 1, v ^= v >> 1)
        if (n & 1u) y ^= v;
    // The top 24 bits, as Rng::nextFloat: below 1.
    return {float(x >> 8) * 0x1p-24f, float(y >> 8) * 0x1p-24f};
}

Vec2f pixelSamplePosition(uint64_t seed, uint64_t pixelIndex, uint64_t sampleIndex) {
    const uint64_t parity = sampleIndex & 1u;
    Rng scramble(seed, pixelSampleStream(pixelIndex, kScrambleStream - parity));
    const uint32_t scrambleX = scramble.nextUInt(), scrambleY = scramble.nextUInt();
    return scrambledSobol02(uint32_t(sampleIndex >> 1), scrambleX, scrambleY);
}

}  // namespace partita
