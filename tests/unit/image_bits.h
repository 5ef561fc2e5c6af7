// Bit-for-bit comparison of images (thread-count independence, sharding, merges).
#pragma once

#include <gtest/gtest.h>

#include <cstring>

#include "image.h"

namespace partita::test {

inline bool sameBits(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
           (a.rgb.empty() ||  // memcmp of null pointers is undefined, even for 0 bytes
            std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0);
}

/// The combined image and every layer, names included, equal bit for bit.
inline void expectSameBits(const LayeredImage& a, const LayeredImage& b) {
    EXPECT_TRUE(sameBits(a.combined, b.combined));
    ASSERT_EQ(a.layers.size(), b.layers.size());
    for (size_t i = 0; i < a.layers.size(); ++i) {
        EXPECT_EQ(a.layers[i].name, b.layers[i].name);
        EXPECT_TRUE(sameBits(a.layers[i].image, b.layers[i].image)) << a.layers[i].name;
    }
}

}  // namespace partita::test
