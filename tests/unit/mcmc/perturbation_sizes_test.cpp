// Chi-square tests of Veach's perturbation sizes (core/mcmc/perturbation_sizes.h): raster
// offsets and direction deflections whose size is log-uniform between s1 and s2, in a direction
// uniform around the current one.
//
// Why these tests: the MCMC perturbations drop the proposal densities from the acceptance ratio
// because the proposals are symmetric, T(a -> b) = T(b -> a). That holds only if the density of
// a move depends on its size alone: the size must follow perturbationSizeDensity (log-uniform),
// the direction of the move must be uniform and independent of the size, and the raster move
// must not depend on where it starts. A wrong exponent, a biased angle or a size-dependent
// direction would make the chain sample a different target without any visible error.
//  - For raster offsets and for deflections about fixed directions (the poles, where frames are
//    fragile, and an oblique one): Pearson chi-square tests of log(size) against the integral of
//    perturbationSizeDensity over each bin, of the azimuth against uniform, and of the joint
//    (size, azimuth) histogram against the product (independence).
//  - perturbationSizeDensity integrates to 1, equals 1 / (s ln(s2/s1)) inside and 0 outside.
//  - A raster offset does not depend on the raster position it starts from.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "chi2.h"
#include "math/vec.h"
#include "mcmc/perturbation_sizes.h"
#include "rng.h"

namespace partita {
namespace {

// Twelve chi-square tests in this file (size, azimuth and joint, for the raster offsets and for
// three directions) share a family-wise false-alarm level of 1e-3.
constexpr double kFamilyAlpha = 1e-3;
constexpr int kChi2Tests = 12;

constexpr int kSizeBins = 20, kAzimuthBins = 24;           // the marginals
constexpr int kJointSizeBins = 8, kJointAzimuthBins = 12;  // the joint histogram

const PerturbationRange kRasterRange{0.1f, 50.f};
const PerturbationRange kDirectionRange{1e-4f, 0.1f};

/// One move: its size (offset length or deflection angle) and its azimuth in [-pi, pi].
struct Move {
    double size = 0, azimuth = 0;
};

void expectFits(const std::vector<double>& observed, const std::vector<double>& probability,
                double n, const std::string& what) {
    test::Pearson r = test::pearson(observed, probability, n);
    EXPECT_GE(r.minExpected, 5) << what;
    EXPECT_GE(r.pValue, test::sidakLevel(kFamilyAlpha, kChi2Tests)) << what << ": " << r.describe();
}

/// The integral of perturbationSizeDensity over [a, b]: 4-point Gauss-Legendre on 16 geometric
/// sub-intervals (the density is smooth inside the range; only interior nodes are used).
double integrateSizeDensity(const PerturbationRange& range, double a, double b) {
    static const double x[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                0.8611363115940526};
    static const double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                0.3478548451374538};
    const int pieces = 16;
    double sum = 0, ratio = std::pow(b / a, 1.0 / pieces);
    for (int i = 0; i < pieces; ++i) {
        double lo = a * std::pow(ratio, i), hi = lo * ratio, c = 0.5 * (lo + hi),
               h = 0.5 * (hi - lo);
        for (int j = 0; j < 4; ++j)
            sum += w[j] * h * perturbationSizeDensity(range, float(c + h * x[j]));
    }
    return sum;
}

/// The edge k of `bins` equal bins of log(size) between log s1 and log s2.
double sizeBinEdge(const PerturbationRange& range, int k, int bins) {
    double s1 = range.smallest, s2 = range.largest;
    return s1 * std::pow(s2 / s1, double(k) / bins);
}

/// The probability of each log(size) bin, by integrating the claimed density.
std::vector<double> sizeBinProbabilities(const PerturbationRange& range, int bins) {
    std::vector<double> p(static_cast<size_t>(bins));
    for (int k = 0; k < bins; ++k)
        p[size_t(k)] = integrateSizeDensity(range, sizeBinEdge(range, k, bins),
                                            sizeBinEdge(range, k + 1, bins));
    return p;
}

int sizeBin(const PerturbationRange& range, double s, int bins) {
    double t = std::log(s / range.smallest) / std::log(double(range.largest) / range.smallest);
    return std::clamp(int(t * bins), 0, bins - 1);  // rounding at the ends stays inside
}

int azimuthBin(double phi, int bins) {
    return std::clamp(int((phi + kPi) / (2 * kPi) * bins), 0, bins - 1);
}

/// Every size lies in [s1, s2] up to `tolerance` (the rounding of the measured size).
void expectSizesInRange(const std::vector<Move>& moves, const PerturbationRange& range,
                        double tolerance) {
    int outside = 0;
    for (const Move& m : moves)
        outside += m.size < range.smallest - tolerance || m.size > range.largest + tolerance;
    EXPECT_EQ(outside, 0) << "moves outside [" << range.smallest << ", " << range.largest << "]";
}

/// The three chi-square tests of a set of moves: log(size), azimuth, and the two jointly.
void expectLogUniformAndIsotropic(const std::vector<Move>& moves, const PerturbationRange& range,
                                  const std::string& what) {
    const double n = double(moves.size());
    std::vector<double> sizes(kSizeBins), azimuths(kAzimuthBins),
        joint(kJointSizeBins * kJointAzimuthBins);
    for (const Move& m : moves) {
        sizes[size_t(sizeBin(range, m.size, kSizeBins))] += 1;
        azimuths[size_t(azimuthBin(m.azimuth, kAzimuthBins))] += 1;
        int k = sizeBin(range, m.size, kJointSizeBins) * kJointAzimuthBins +
                azimuthBin(m.azimuth, kJointAzimuthBins);
        joint[size_t(k)] += 1;
    }
    expectFits(sizes, sizeBinProbabilities(range, kSizeBins), n, what + ", log size");
    expectFits(azimuths, std::vector<double>(kAzimuthBins, 1.0 / kAzimuthBins), n,
               what + ", azimuth");
    std::vector<double> jointProbability;
    for (double p : sizeBinProbabilities(range, kJointSizeBins))
        for (int j = 0; j < kJointAzimuthBins; ++j)
            jointProbability.push_back(p / kJointAzimuthBins);
    expectFits(joint, jointProbability, n, what + ", joint (size, azimuth)");
}

std::vector<Move> rasterMoves(int count) {
    Rng rng(31, 1);
    std::vector<Move> moves;
    for (int i = 0; i < count; ++i) {
        Vec2f d = perturbRaster({0, 0}, kRasterRange, {rng.nextFloat(), rng.nextFloat()});
        moves.push_back(
            {std::hypot(double(d.x), double(d.y)), std::atan2(double(d.y), double(d.x))});
    }
    return moves;
}

TEST(PerturbationSizes, RasterOffsetsAreLogUniformAndIsotropic) {
    EXPECT_NEAR(integrateSizeDensity(kRasterRange, kRasterRange.smallest, kRasterRange.largest), 1,
                64 * FLT_EPSILON);
    std::vector<Move> moves = rasterMoves(200000);
    expectSizesInRange(moves, kRasterRange, 4 * FLT_EPSILON * kRasterRange.largest);
    expectLogUniformAndIsotropic(moves, kRasterRange, "raster");
}

// Directions in double, for the measurements.
struct Dir {
    double x, y, z;
};
Dir toDir(Vec3f v) { return {v.x, v.y, v.z}; }
double dot(Dir a, Dir b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Dir cross(Dir a, Dir b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
Dir minus(Dir a, Dir b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Dir unit(Dir a) {
    double l = std::sqrt(dot(a, a));
    return {a.x / l, a.y / l, a.z / l};
}

/// The deflection from w to w2: the angle by 2 asin(|w2 - w| / 2), exact for tiny angles where
/// acos(dot) is not, and the azimuth in the test's own frame (e1, e2, w).
Move deflection(Dir w, Dir w2) {
    Dir helper = std::abs(w.x) < 0.9 ? Dir{1, 0, 0} : Dir{0, 1, 0};
    Dir e1 = unit(cross(w, helper)), e2 = cross(w, e1), d = minus(w2, w);
    return {2 * std::asin(0.5 * std::sqrt(dot(d, d))), std::atan2(dot(d, e2), dot(d, e1))};
}

/// Deflections of w; every perturbed direction must be a unit vector.
std::vector<Move> directionMoves(Vec3f w, uint64_t stream, int count) {
    Rng rng(32, stream);
    std::vector<Move> moves;
    int notUnit = 0;
    for (int i = 0; i < count; ++i) {
        Vec3f w2 = perturbDirection(w, kDirectionRange, {rng.nextFloat(), rng.nextFloat()});
        notUnit += !(std::abs(std::sqrt(dot(toDir(w2), toDir(w2))) - 1) <= 4 * FLT_EPSILON);
        moves.push_back(deflection(toDir(w), toDir(w2)));
    }
    EXPECT_EQ(notUnit, 0) << "perturbed directions of length != 1";
    return moves;
}

TEST(PerturbationSizes, DirectionDeflectionsAreLogUniformAndIsotropic) {
    const Vec3f directions[] = {{0, 0, 1}, {0, 0, -1}, normalize(Vec3f(0.3f, -0.5f, 0.81f))};
    uint64_t stream = 0;
    for (Vec3f w : directions) {
        std::ostringstream name;
        name << "w = (" << w.x << ", " << w.y << ", " << w.z << ")";
        std::vector<Move> moves = directionMoves(w, stream++, 100000);
        // The measured angle carries the float rounding of w2's components, ~1e-7 absolute.
        expectSizesInRange(moves, kDirectionRange, 16 * FLT_EPSILON);
        expectLogUniformAndIsotropic(moves, kDirectionRange, name.str());
    }
}

TEST(PerturbationSizes, SizeDensityIsLogUniform) {
    for (const PerturbationRange& range : {kRasterRange, kDirectionRange}) {
        double s1 = range.smallest, s2 = range.largest, norm = std::log(s2 / s1);
        for (int k = 0; k <= 8; ++k) {
            float s = float(s1 * std::pow(s2 / s1, k / 8.0));
            double expected = 1 / (s * norm);
            EXPECT_NEAR(perturbationSizeDensity(range, s), expected, 8 * FLT_EPSILON * expected)
                << "s = " << s;
        }
        EXPECT_EQ(perturbationSizeDensity(range, std::nextafter(range.smallest, 0.f)), 0);
        EXPECT_EQ(perturbationSizeDensity(range, std::nextafter(range.largest, 1e30f)), 0);
        EXPECT_NEAR(integrateSizeDensity(range, s1, s2), 1, 64 * FLT_EPSILON);
    }
}

TEST(PerturbationSizes, RasterOffsetDoesNotDependOnTheStart) {
    // With the offset independent of the start and its density a function of |offset| alone
    // (the size density over the circle 2 pi |offset|, see the chi-square tests above), the
    // density of moving a -> b is that of b -> a: the proposal is symmetric.
    const Vec2f starts[] = {{3.25f, -7.5f}, {640.5f, 359.5f}, {-0.125f, 1919.75f}};
    Rng rng(33, 0);
    for (int i = 0; i < 1000; ++i) {
        Vec2f u{rng.nextFloat(), rng.nextFloat()};
        Vec2f base = perturbRaster({0, 0}, kRasterRange, u);
        for (Vec2f a : starts) {
            Vec2f d = perturbRaster(a, kRasterRange, u) - a;
            // The sum a + offset rounds to the float spacing at |a| + s2.
            double tolerance =
                2 * FLT_EPSILON * (std::max(std::abs(a.x), std::abs(a.y)) + kRasterRange.largest);
            EXPECT_NEAR(d.x, base.x, tolerance);
            EXPECT_NEAR(d.y, base.y, tolerance);
        }
    }
}

}  // namespace
}  // namespace partita
