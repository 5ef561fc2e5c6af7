// PCG32 random number generator (O'Neill 2014) with selectable streams.
//
// Every sample the renderer draws comes from an Rng seeded by (job seed, stream id), where the
// stream id names the pixel and the sample index. Two consequences the rest of the design relies
// on: images do not depend on the thread count or tile order, and any path can be regenerated
// later from (seed, pixel, sample index) alone (the pre-pass of paper Section 4.2 does this).
#pragma once

#include <cstdint>

namespace partita {

/// SplitMix64 finaliser: a strong 64-bit mix used to derive seeds and streams.
constexpr uint64_t mix64(uint64_t z) {
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

class Rng {
  public:
    Rng() { seed(0, 0); }
    Rng(uint64_t seedValue, uint64_t stream) { seed(seedValue, stream); }

    void seed(uint64_t seedValue, uint64_t stream) {
        state_ = 0;
        inc_ = (mix64(stream) << 1u) | 1u;
        nextUInt();
        state_ += mix64(seedValue);
        nextUInt();
    }

    uint32_t nextUInt() {
        uint64_t old = state_;
        state_ = old * 6364136223846793005ull + inc_;
        uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
        uint32_t rot = uint32_t(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((-rot) & 31));
    }

    /// Uniform in [0, 1): 24 random mantissa bits, never returns 1.
    float nextFloat() { return float(nextUInt() >> 8) * 0x1p-24f; }

    /// Uniform integer in [0, bound) without modulo bias.
    uint32_t nextBounded(uint32_t bound) {
        uint32_t threshold = (-bound) % bound;
        for (;;) {
            uint32_t r = nextUInt();
            if (r >= threshold) return r % bound;
        }
    }

    /// The full generator state, enough to regenerate everything drawn after this point.
    struct State {
        uint64_t state, inc;
    };
    State saveState() const { return {state_, inc_}; }
    void restoreState(State s) {
        state_ = s.state;
        inc_ = s.inc;
    }

  private:
    uint64_t state_ = 0, inc_ = 1;
};

/// Stream id of sample `sampleIndex` of pixel `pixelIndex`: unique per (pixel, sample) pair.
constexpr uint64_t pixelSampleStream(uint64_t pixelIndex, uint64_t sampleIndex) {
    return mix64(pixelIndex * 0x100000001b3ull ^ mix64(sampleIndex + 0x51ed270b27ull));
}

}  // namespace partita
