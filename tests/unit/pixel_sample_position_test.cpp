// Tests of where a pixel's samples fall inside it (pixel_sample_position.h): each point uniform
// over the pixel (chi-square over many pixels), each parity's first 2^k points stratified in
// every elementary interval, and the even and odd halves independent of each other.
#include <gtest/gtest.h>

#include <set>
#include <vector>

#include "chi2.h"
#include "pixel_sample_position.h"

namespace partita {
namespace {

constexpr uint64_t kSeed = 7;
constexpr int kTests = 2;  // the chi-square tests of this file (Sidak correction)

int cell(float u, int cells) { return std::min(cells - 1, int(u * float(cells))); }

TEST(PixelSamplePosition, EveryParitysFirstPointsFillEveryElementaryInterval) {
    // The first 2^k points of one parity's sequence (samples s, s + 2, ...): for each shape
    // 2^a x 2^(k-a) of elementary interval, one point in each.
    constexpr int k = 6, n = 1 << k;
    for (uint64_t pixel : {0ull, 1ull, 49151ull})
        for (uint64_t parity : {0ull, 1ull})
            for (int a = 0; a <= k; ++a) {
                std::set<std::pair<int, int>> seen;
                for (int i = 0; i < n; ++i) {
                    Vec2f u = pixelSamplePosition(kSeed, pixel, 2 * uint64_t(i) + parity);
                    ASSERT_GE(u.x, 0.0f);
                    ASSERT_LT(u.x, 1.0f);
                    ASSERT_GE(u.y, 0.0f);
                    ASSERT_LT(u.y, 1.0f);
                    seen.insert({cell(u.x, 1 << a), cell(u.y, 1 << (k - a))});
                }
                EXPECT_EQ(int(seen.size()), n)
                    << "pixel " << pixel << " parity " << parity << " shape 2^" << a;
            }
}

TEST(PixelSamplePosition, APointIsUniformOverThePixelAcrossPixels) {
    // Sample 5 of 100000 pixels on an 8 x 8 grid of cells: uniform (the scramble is random).
    constexpr int cells = 8, pixels = 100000;
    std::vector<double> counts(cells * cells, 0), p(cells * cells, 1.0 / (cells * cells));
    for (uint64_t pixel = 0; pixel < pixels; ++pixel) {
        Vec2f u = pixelSamplePosition(kSeed, pixel, 5);
        counts[size_t(cell(u.y, cells) * cells + cell(u.x, cells))] += 1;
    }
    test::Pearson r = test::pearson(counts, p, pixels);
    EXPECT_GT(r.pValue, test::sidakLevel(1e-3, kTests)) << r.describe();
}

TEST(PixelSamplePosition, TheEvenAndOddHalvesAreIndependent) {
    // Sample 0 (even) and sample 1 (odd) of a pixel: the joint of their 4 x 4 cells is uniform
    // over 256 cells. One (0, 2)-sequence over all indices would put them in opposite halves.
    constexpr int cells = 4, pixels = 200000;
    std::vector<double> counts(256, 0), p(256, 1.0 / 256);
    for (uint64_t pixel = 0; pixel < pixels; ++pixel) {
        Vec2f a = pixelSamplePosition(kSeed, pixel, 0), b = pixelSamplePosition(kSeed, pixel, 1);
        int ca = cell(a.y, cells) * cells + cell(a.x, cells);
        int cb = cell(b.y, cells) * cells + cell(b.x, cells);
        counts[size_t(ca * 16 + cb)] += 1;
    }
    test::Pearson r = test::pearson(counts, p, pixels);
    EXPECT_GT(r.pValue, test::sidakLevel(1e-3, kTests)) << r.describe();
}

}  // namespace
}  // namespace partita
