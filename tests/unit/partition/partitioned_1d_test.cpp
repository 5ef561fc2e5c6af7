// The 1D example of paper Section 4.1 (Figure 3): path space partitioning (Eq. 5-10) on a
// function of one variable, integrated by Metropolis-Hastings with a Gaussian random-walk
// proposal, without and with partitioning, using the renderer's own step (metropolisStep of
// core/mcmc/metropolis.h, expected-value splats).
//
// The target f on [0, 1) has a wide dark region [0, 0.75) (about 0.5) and a narrow bright one
// [0.75, 1) (about 5, a caustic in miniature), each with a smooth bump, so that the integral of
// each region and of each of the 16 bins of the "image" is known in closed form. The proposal is
// narrow: a chain crosses the boundary a few times in its 500 steps, the paper's low-sample
// regime, so the time the unpartitioned chain spends in each region is far from its expected
// share.
//  - Unpartitioned (Eq. 4): one chain on [0, 1), I_j = b / N sum of splats in bin j.
//  - Partitioned (Eq. 8-10): the two regions are the partitions, one chain restricted to each (a
//    proposal leaving it is rejected), the N samples split in proportion to P(i) = b_i / sum b
//    (Eq. 10, stratified), I_j = sum_i b_i / N_i sum of chain i's splats in bin j.
// Both use the exact normalising constants b and b_i, so the comparison isolates the sampling,
// as the paper's figure does; and both start their chains in the stationary distribution (an
// exact draw, standing in for the renderer's start-up resampling), so both are unbiased at any
// chain length. Why these tests: partitioning must not bias the image (a chain that leaks out
// of its partition does, and the same check sees it), and it is only worth its complication if
// it lowers the error where the paper says it does; the measured variance ratio is printed
// (the paper reports 89x for its own function).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "mcmc/metropolis.h"
#include "rng.h"
#include "statistics.h"

namespace partita {
namespace {

constexpr double kTwoPi = 6.283185307179586;
constexpr int kBins = 16;
constexpr int kSteps = 500;      // samples per estimate, both estimators
constexpr double kSigma = 0.05;  // standard deviation of the random-walk proposal
constexpr int kSeeds = 400;      // independent estimates per estimator and statistic

struct Interval {
    double lo, hi;
    bool contains(double x) const { return x >= lo && x < hi; }
};

/// One region of f: base + bump (1 - cos(2 pi (x - lo) / (hi - lo))) on [lo, hi), a smooth
/// bump vanishing at the region's ends, so f jumps only at the boundary between regions.
struct Region {
    Interval span;
    double base, bump;
    double width() const { return span.hi - span.lo; }
    double f(double x) const {
        return base + bump * (1 - std::cos(kTwoPi * (x - span.lo) / width()));
    }
    /// The integral of f over [lo, x], x in [lo, hi].
    double primitive(double x) const {
        double t = x - span.lo;
        return (base + bump) * t - bump * width() / kTwoPi * std::sin(kTwoPi * t / width());
    }
    /// The integral of f over the part of [a, b] inside the region.
    double integral(double a, double b) const {
        a = std::max(a, span.lo);
        b = std::min(b, span.hi);
        return b > a ? primitive(b) - primitive(a) : 0;
    }
};

constexpr std::array<Region, 2> kRegions = {Region{{0, 0.75}, 0.5, 0.2}, Region{{0.75, 1}, 5, 1}};
constexpr double kFMax = 7;  // max of f: the bright region's bump top
constexpr Interval kDomain = {0, 1};

double f(double x) {
    for (const Region& r : kRegions)
        if (r.span.contains(x)) return r.f(x);
    return 0;
}

double regionIntegral(int i) { return kRegions[size_t(i)].integral(0, 1); }
double totalIntegral() { return regionIntegral(0) + regionIntegral(1); }

using Image = std::array<double, kBins>;

Image exactBins() {
    Image bins{};
    for (int j = 0; j < kBins; ++j)
        for (const Region& r : kRegions)
            bins[size_t(j)] += r.integral(double(j) / kBins, double(j + 1) / kBins);
    return bins;
}

int binOf(double x) { return std::clamp(int(x * kBins), 0, kBins - 1); }

/// A standard normal by Box-Muller (1 - u is in (0, 1], so the log is finite).
double gaussian(Rng& rng) {
    double radius = std::sqrt(-2 * std::log(1.0 - rng.nextFloat()));
    return radius * std::cos(kTwoPi * rng.nextFloat());
}

/// An exact draw from f restricted to `span`, by rejection from the uniform.
double sampleStationary(Interval span, Rng& rng) {
    for (;;) {
        double x = span.lo + (span.hi - span.lo) * rng.nextFloat();
        if (span.contains(x) && rng.nextFloat() * kFMax < f(x)) return x;
    }
}

/// `steps` steps of a chain started in `start` that may move within `moves`, splatted into
/// `image` with weight `scale` per step (b / N of Eq. 4, b_i / N_i of Eq. 8). The proposal is
/// symmetric, T(y->x) / T(x->y) = 1; one outside `moves` is no proposal, a rejection.
void runChain(Interval start, Interval moves, int steps, double scale, Rng& rng, Image& image) {
    double x = sampleStationary(start, rng), fx = f(x);
    auto propose = [moves](const double& from, Rng& r) {
        Proposal<double> p;
        double y = from + kSigma * gaussian(r);
        if (moves.contains(y)) p = {true, y, f(y), 1.0};
        return p;
    };
    auto splat = [&image, scale](const double& s, double w) {
        image[size_t(binOf(s))] += scale * w;
    };
    for (int k = 0; k < steps; ++k) metropolisStep(x, fx, rng, propose, splat);
}

/// Eq. 4 with one chain on the whole domain.
Image unpartitioned(uint64_t seed) {
    Rng rng(seed, 0);
    Image image{};
    runChain(kDomain, kDomain, kSteps, totalIntegral() / kSteps, rng, image);
    return image;
}

/// N_i = N P(i), P(i) = b_i / sum b (Eq. 10, stratified), rounded; the last takes the rest.
std::array<int, 2> stratifiedAllocation() {
    int dark = int(std::lround(kSteps * regionIntegral(0) / totalIntegral()));
    return {dark, kSteps - dark};
}

/// Eq. 8-10: one chain per partition with its own b_i; `leak` lets the chains leave their
/// partitions (a bug the convergence test must catch).
Image partitionedImpl(uint64_t seed, bool leak) {
    const std::array<int, 2> steps = stratifiedAllocation();
    Image image{};
    for (int i = 0; i < 2; ++i) {
        Rng rng(seed, uint64_t(i + 1));
        Interval span = kRegions[size_t(i)].span;
        double scale = regionIntegral(i) / steps[size_t(i)];
        runChain(span, leak ? kDomain : span, steps[size_t(i)], scale, rng, image);
    }
    return image;
}

Image partitioned(uint64_t seed) { return partitionedImpl(seed, false); }
Image leakingPartitioned(uint64_t seed) { return partitionedImpl(seed, true); }

using Estimator = Image (*)(uint64_t);

std::vector<Image> estimates(Estimator estimator, uint64_t firstSeed) {
    std::vector<Image> images;
    for (int s = 0; s < kSeeds; ++s) images.push_back(estimator(firstSeed + uint64_t(s)));
    return images;
}

struct BinCheck {
    int failures = 0;
    std::string detail;
};

/// Compares each bin's mean over the estimates with the exact bin (statistics.h tolerance at
/// the Sidak level for `comparisons`).
BinCheck checkBins(const std::vector<Image>& images, int comparisons) {
    const Image exact = exactBins();
    BinCheck check;
    std::ostringstream os;
    for (int j = 0; j < kBins; ++j) {
        std::vector<double> values;
        for (const Image& image : images) values.push_back(image[size_t(j)]);
        test::MeanAndError m = test::meanAndError(values);
        double tolerance = test::statisticalTolerance(m, exact[size_t(j)], comparisons);
        if (std::abs(m.mean - exact[size_t(j)]) <= tolerance) continue;
        ++check.failures;
        os << " bin " << j << ": " << m.mean << " vs " << exact[size_t(j)] << " (tolerance "
           << tolerance << ");";
    }
    check.detail = os.str();
    return check;
}

/// Per seed, the squared error summed over bins [firstBin, lastBin).
std::vector<double> squaredErrors(const std::vector<Image>& images, int firstBin, int lastBin) {
    const Image exact = exactBins();
    std::vector<double> errors;
    for (const Image& image : images) {
        double sum = 0;
        for (int j = firstBin; j < lastBin; ++j) {
            double e = image[size_t(j)] - exact[size_t(j)];
            sum += e * e;
        }
        errors.push_back(sum);
    }
    return errors;
}

/// Ratio of two mean squared errors and its first-order standard error.
std::string describeRatio(const test::MeanAndError& a, const test::MeanAndError& b) {
    double ratio = a.mean / b.mean;
    double rel = std::hypot(a.standardError / a.mean, b.standardError / b.mean);
    std::ostringstream os;
    os << ratio << "x +- " << ratio * rel << " (" << a.mean << " +- " << a.standardError << " vs "
       << b.mean << " +- " << b.standardError << ")";
    return os.str();
}

TEST(PartitionedMcmc1D, ClosedFormBinsMatchQuadrature) {
    // The exact answers the other tests use: each bin by the midpoint rule on a fine grid (f is
    // smooth inside a bin, the boundary being a bin edge), and the bins summing to sum b_i.
    const Image exact = exactBins();
    const int points = 4096;
    double sum = 0;
    for (int j = 0; j < kBins; ++j) {
        double quadrature = 0, h = 1.0 / (kBins * points);
        for (int k = 0; k < points; ++k) quadrature += h * f((j * points + k + 0.5) * h);
        EXPECT_NEAR(exact[size_t(j)], quadrature, 1e-8) << "bin " << j;
        sum += exact[size_t(j)];
    }
    EXPECT_NEAR(sum, totalIntegral(), 1e-12);
    EXPECT_DOUBLE_EQ(kRegions[0].span.hi * kBins, 12.0);  // the boundary is a bin edge
    const std::array<int, 2> steps = stratifiedAllocation();
    EXPECT_GE(std::min(steps[0], steps[1]), 1);
    EXPECT_EQ(steps[0] + steps[1], kSteps);
}

TEST(PartitionedMcmc1D, BothEstimatorsConvergeToExactBins) {
    // Every bin's mean over independent seeds agrees with the exact bin; one Sidak family over
    // the bins of both estimators.
    const int comparisons = 2 * kBins;
    BinCheck plain = checkBins(estimates(unpartitioned, 1000), comparisons);
    EXPECT_EQ(plain.failures, 0) << "unpartitioned:" << plain.detail;
    BinCheck split = checkBins(estimates(partitioned, 2000), comparisons);
    EXPECT_EQ(split.failures, 0) << "partitioned:" << split.detail;

    // The check has teeth: chains that leave their partitions but keep its b_i are rejected.
    EXPECT_GT(checkBins(estimates(leakingPartitioned, 3000), comparisons).failures, 0);
}

TEST(PartitionedMcmc1D, PartitioningLowersErrorAtLowSampleCount) {
    // Squared error over all bins, per seed, for each estimator at the same N; both are
    // unbiased (test above), so the mean squared error is the summed variance of the bins.
    // Partitioning must be better by more than a two-sample Student-t tolerance (two-sided at
    // 1e-3, so conservative for this one-sided claim).
    const int dark = kBins * 3 / 4;
    const std::vector<Image> plainImages = estimates(unpartitioned, 4000);
    const std::vector<Image> splitImages = estimates(partitioned, 5000);
    test::MeanAndError plain = test::meanAndError(squaredErrors(plainImages, 0, kBins));
    test::MeanAndError split = test::meanAndError(squaredErrors(splitImages, 0, kBins));
    test::MeanAndError plainDark = test::meanAndError(squaredErrors(plainImages, 0, dark));
    test::MeanAndError splitDark = test::meanAndError(squaredErrors(splitImages, 0, dark));
    std::printf("[ info     ] variance ratio unpartitioned / partitioned, N = %d: %s\n", kSteps,
                describeRatio(plain, split).c_str());
    std::printf("[ info     ] dark region's bins only: %s\n",
                describeRatio(plainDark, splitDark).c_str());
    EXPECT_GT(plain.mean - split.mean, test::twoSampleTolerance(plain, split))
        << describeRatio(plain, split);

    // The test has teeth the other way too: two independent batches of the same estimator are
    // not told apart by it.
    test::MeanAndError again =
        test::meanAndError(squaredErrors(estimates(unpartitioned, 6000), 0, kBins));
    EXPECT_LE(std::abs(plain.mean - again.mean), test::twoSampleTolerance(plain, again))
        << describeRatio(plain, again);
}

}  // namespace
}  // namespace partita
