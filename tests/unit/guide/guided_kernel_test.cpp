// The discrete heart of the guided image perturbation (paper Eq. 16-18), exactly: on a small
// pixel grid with a given S' and target f*, the full transition matrix of the guided move
// (candidate choice by guided_choice.h, acceptance by metropolis.h with guidedProposalRatio)
// leaves f* invariant and satisfies detailed balance to rounding. The grid is small enough that
// candidates fall off the image (S' = 0 there), the offsets collide after rounding
// (multiplicities), some pixels have S' = 0 (never proposed, never left by this move) and some
// f* = 0 (never entered).
//
// Negative controls show the check can fail: a ratio that forgets the candidate sums (the
// paper's normalisation), and one that takes the proposal as symmetric. Without Delta's
// negations the chain stays exact but rejects every move whose reverse is not a candidate.
//
// Also: Delta (offsets.h) is symmetric, has the centre, lies in the disk up to rounding and has
// exactly |Y'| entries; chooseCandidate draws in proportion to the weights (chi-square).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "chi2.h"
#include "guide/guided_choice.h"
#include "guide/offsets.h"
#include "mcmc/metropolis.h"
#include "rng.h"

namespace partita {
namespace {

constexpr int kWidth = 7, kHeight = 5, kPixels = kWidth * kHeight;

struct Grid {
    std::vector<double> target, sPrime;  // f* and S' per pixel
};

/// f* and S' drawn once from a fixed seed; a few of each are exactly 0.
Grid makeGrid(uint64_t seed) {
    Rng rng(seed, 7);
    Grid g;
    for (int i = 0; i < kPixels; ++i) {
        g.target.push_back(i % 11 == 3 ? 0.0 : 0.1 + 4.0 * rng.nextFloat());
        g.sPrime.push_back(i % 13 == 5 ? 0.0 : 0.05 + 2.0 * rng.nextFloat());
    }
    return g;
}

using Matrix = std::vector<std::vector<double>>;

/// The proposal-ratio rule under test: the real one, or a broken one for the negative control.
enum class Ratio { Eq16, WithoutSums, One };

/// P(p -> q) of the guided move from every pixel: choose k with weight S'(p + delta_k), accept
/// with min(1, f*(q) T(q -> p) / (f*(p) T(p -> q))); the rest stays at p.
Matrix transitionMatrix(const Grid& g, const std::vector<PixelOffset>& delta, Ratio rule) {
    auto sPrime = [&](int x, int y) { return g.sPrime[size_t(y * kWidth + x)]; };
    Matrix P(kPixels, std::vector<double>(kPixels, 0.0));
    const std::vector<int> back = oppositeOffsets(delta);
    for (int p = 0; p < kPixels; ++p) {
        int px = p % kWidth, py = p / kWidth;
        CandidateWeights atP;
        gatherCandidates(delta, px, py, kWidth, kHeight, sPrime, atP);
        double leave = 0;
        for (size_t k = 0; k < delta.size() && atP.sum > 0; ++k) {
            if (!(atP.weights[k] > 0)) continue;
            int qx = px + delta[k].dx, qy = py + delta[k].dy, q = qy * kWidth + qx;
            double choose = double(atP.weights[k]) / atP.sum;
            CandidateWeights atQ;
            gatherCandidates(delta, qx, qy, kWidth, kHeight, sPrime, atQ);
            double ratio = guidedProposalRatio(atP, atQ, int(k), back[k]);
            if (rule == Ratio::WithoutSums) ratio *= atQ.sum / atP.sum;
            if (rule == Ratio::One) ratio = 1;
            double a = acceptanceProbability(g.target[size_t(p)], g.target[size_t(q)], ratio);
            if (q == p) continue;  // staying is the remainder
            P[size_t(p)][size_t(q)] += choose * a;
            leave += choose * a;
        }
        P[size_t(p)][size_t(p)] = 1 - leave;
    }
    return P;
}

/// The largest |pi(p) P(p,q) - pi(q) P(q,p)| relative to pi's largest entry, and the largest
/// |(pi P)(q) - pi(q)|, pi = f* normalised.
struct BalanceError {
    double detailed = 0, stationary = 0;
};

BalanceError balanceError(const Grid& g, const Matrix& P) {
    double total = 0;
    for (double f : g.target) total += f;
    std::vector<double> pi;
    for (double f : g.target) pi.push_back(f / total);
    double piMax = *std::max_element(pi.begin(), pi.end());
    BalanceError e;
    for (int q = 0; q < kPixels; ++q) {
        double flowIn = 0;
        for (int p = 0; p < kPixels; ++p) {
            flowIn += pi[size_t(p)] * P[size_t(p)][size_t(q)];
            double d =
                pi[size_t(p)] * P[size_t(p)][size_t(q)] - pi[size_t(q)] * P[size_t(q)][size_t(p)];
            e.detailed = std::max(e.detailed, std::abs(d) / piMax);
        }
        e.stationary = std::max(e.stationary, std::abs(flowIn - pi[size_t(q)]) / piMax);
    }
    return e;
}

int offGridCandidates(const std::vector<PixelOffset>& delta) {
    int off = 0;
    for (const PixelOffset& o : delta)
        if (std::abs(o.dx) >= kWidth / 2 || std::abs(o.dy) >= kHeight / 2) ++off;
    return off;
}

bool hasCollisions(const std::vector<PixelOffset>& delta) {
    std::map<std::pair<int, int>, int> seen;
    for (const PixelOffset& o : delta)
        if (++seen[{o.dx, o.dy}] > 1 && !(o.dx == 0 && o.dy == 0)) return true;
    return false;
}

TEST(GuidedPerturbation, Eq16DetailedBalanceOnAGrid) {
    // |Y'| = 33 in a radius of 3.5 pixels on a 7 x 5 grid: rounded offsets collide, and from
    // every border pixel some candidates leave the image. Also an even |Y'| (centre twice).
    for (int count : {33, 32}) {
        std::vector<PixelOffset> delta = guideOffsets(count, 3.5f);
        ASSERT_TRUE(hasCollisions(delta));
        ASSERT_GT(offGridCandidates(delta), 0);
        for (uint64_t seed : {1, 2, 3}) {
            Grid g = makeGrid(seed);
            Matrix P = transitionMatrix(g, delta, Ratio::Eq16);
            for (const auto& row : P) {
                double sum = 0;
                for (double v : row) {
                    EXPECT_GE(v, -1e-15);
                    sum += v;
                }
                EXPECT_NEAR(sum, 1.0, 1e-12);
            }
            BalanceError e = balanceError(g, P);
            EXPECT_LT(e.detailed, 1e-14) << "|Y'| = " << count << ", seed " << seed;
            EXPECT_LT(e.stationary, 1e-13) << "|Y'| = " << count << ", seed " << seed;
            // Not a trivial chain: most pixels with f* > 0 are left with positive probability.
            int moving = 0;
            for (int p = 0; p < kPixels; ++p) moving += P[size_t(p)][size_t(p)] < 1 - 1e-9;
            EXPECT_GT(moving, kPixels / 2);
        }
    }
}

TEST(GuidedPerturbation, BreaksWithoutTheSumsOrWithASymmetricRatio) {
    Grid g = makeGrid(1);
    std::vector<PixelOffset> delta = guideOffsets(33, 3.5f);
    EXPECT_GT(balanceError(g, transitionMatrix(g, delta, Ratio::WithoutSums)).detailed, 1e-4);
    EXPECT_GT(balanceError(g, transitionMatrix(g, delta, Ratio::One)).detailed, 1e-4);
}

/// The ratio reads S'(p) at the offset back from q, the multiplicities cancelling: Delta must
/// hold every shift as often as its negation, and a set without the negations is refused.
TEST(GuidedPerturbation, OffsetsWithoutTheirNegationsAreRefused) {
    std::vector<PixelOffset> delta = guideOffsets(33, 3.5f);
    const std::vector<int> back = oppositeOffsets(delta);
    for (size_t k = 0; k < delta.size(); ++k) {
        EXPECT_EQ(delta[size_t(back[k])].dx, -delta[k].dx);
        EXPECT_EQ(delta[size_t(back[k])].dy, -delta[k].dy);
    }
    std::vector<PixelOffset> oneSided(delta.begin(), delta.begin() + 17);  // first half, centre
    EXPECT_THROW(oppositeOffsets(oneSided), std::invalid_argument);
    // Each shift present both ways, but (1, 0) twice and (-1, 0) once.
    EXPECT_THROW(oppositeOffsets({{1, 0}, {1, 0}, {-1, 0}, {0, 0}}), std::invalid_argument);
}

TEST(GuidedPerturbation, HandMadeCollisionsAtTheBorder) {
    // Each shift twice and the centre three times: multiplicities 2 and 3, corners with half
    // the candidates off the image.
    std::vector<PixelOffset> delta = {{1, 0}, {1, 0},  {0, 2},  {0, 0}, {0, 0},
                                      {0, 0}, {-1, 0}, {-1, 0}, {0, -2}};
    for (uint64_t seed : {4, 5}) {
        Grid g = makeGrid(seed);
        BalanceError e = balanceError(g, transitionMatrix(g, delta, Ratio::Eq16));
        EXPECT_LT(e.detailed, 1e-14);
        EXPECT_LT(e.stationary, 1e-13);
    }
}

TEST(GuideOffsets, SymmetricWithTheCentreInsideTheDiskAndOfSizeY) {
    for (int count : {1, 2, 3, 8, 9, 64, 127, 128, 129}) {
        for (float radius : {0.0f, 1.0f, 4.0f, 16.0f, 40.0f}) {
            std::vector<PixelOffset> delta = guideOffsets(count, radius);
            ASSERT_EQ(int(delta.size()), count);
            std::map<std::pair<int, int>, int> multiplicity;
            for (const PixelOffset& o : delta) {
                ++multiplicity[{o.dx, o.dy}];
                // Rounding to whole pixels moves an offset by at most half a diagonal.
                EXPECT_LE(std::hypot(double(o.dx), double(o.dy)), radius + std::sqrt(0.5) + 1e-9);
            }
            EXPECT_GE((multiplicity[{0, 0}]), 1);
            for (const auto& [shift, m] : multiplicity)
                EXPECT_EQ((multiplicity[{-shift.first, -shift.second}]), m)
                    << "|Y'| " << count << ", R " << radius;
            // The centre, then the negations of the first half.
            int half = (count - 1) / 2;
            for (int k = 0; k < half; ++k) {
                EXPECT_EQ(delta[size_t(count - half + k)].dx, -delta[size_t(k)].dx);
                EXPECT_EQ(delta[size_t(count - half + k)].dy, -delta[size_t(k)].dy);
            }
            EXPECT_EQ(delta[size_t(half)], (PixelOffset{0, 0}));
        }
    }
    // r = R zeta^2 puts more candidates near the centre: for the paper's |Y'| = 128, R = 16,
    // over half of the first half lies within R / 4 (a uniform disk: 1 / 16).
    std::vector<PixelOffset> delta = guideOffsets(128, 16);
    int inner = 0;
    for (int k = 0; k < 63; ++k) inner += std::hypot(delta[size_t(k)].dx, delta[size_t(k)].dy) <= 4;
    EXPECT_GT(inner, 63 / 2);
    EXPECT_THROW(guideOffsets(0, 4), std::invalid_argument);
    EXPECT_THROW(guideOffsets(8, -1), std::invalid_argument);
}

TEST(GuidedChoice, ChoosesInProportionToTheWeightsChiSquare) {
    CandidateWeights c;
    c.weights = {0.5f, 0.0f, 3.0f, 1.25f, 0.0f, 2.0f, 0.25f, 4.0f};
    for (float w : c.weights) c.sum += double(w);
    Rng rng(11, 3);
    const int n = 200000;
    std::vector<double> counts(c.weights.size(), 0.0), probability;
    for (int i = 0; i < n; ++i) ++counts[size_t(chooseCandidate(c, rng.nextFloat()))];
    for (float w : c.weights) probability.push_back(double(w) / c.sum);
    for (size_t k = 0; k < c.weights.size(); ++k)
        if (c.weights[k] == 0) {
            EXPECT_EQ(counts[k], 0);
        }
    test::Pearson r = test::pearson(counts, probability, n);
    EXPECT_GT(r.pValue, 1e-3) << r.describe();
    CandidateWeights empty;
    empty.weights = {0.0f, 0.0f};
    EXPECT_EQ(chooseCandidate(empty, 0.5), -1);
}

}  // namespace
}  // namespace partita
