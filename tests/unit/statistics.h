// Statistics for comparing estimators with known answers: mean and standard error over
// independent seeds, and Student-t critical values so that a tolerance derived from a handful of
// seeds is honest about how well it knows the variance.
//
// A comparison of the mean of n independent estimates against the exact value passes when
// |mean - exact| <= t(1 - a/2, n - 1) * standardError, where a is the per-comparison level.
// Tests that make m comparisons use the Sidak level a = 1 - (1 - alpha)^(1/m) so the chance that
// any comparison of a correct estimator fails stays at alpha (1e-3 by default). Seeds are fixed,
// so runs are deterministic; the level bounds the chance a correct renderer was unlucky.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace partita::test {

struct MeanAndError {
    double mean = 0, standardError = 0;
    int count = 0;
};

inline MeanAndError meanAndError(const std::vector<double>& xs) {
    MeanAndError r;
    r.count = int(xs.size());
    double n = double(xs.size());
    for (double x : xs) r.mean += x / n;
    double var = 0;
    for (double x : xs) var += (x - r.mean) * (x - r.mean) / (n - 1);
    r.standardError = std::sqrt(var / n);
    return r;
}

/// Regularised incomplete beta I_x(a, b) by its continued fraction (modified Lentz), using the
/// symmetry I_x(a, b) = 1 - I_{1-x}(b, a) where the fraction converges slowly.
inline double regularizedBeta(double x, double a, double b) {
    if (x <= 0) return 0;
    if (x >= 1) return 1;
    if (x > (a + 1) / (a + b + 2)) return 1 - regularizedBeta(1 - x, b, a);
    double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) +
                            b * std::log(1 - x)) /
                   a;
    const double tiny = 1e-300;
    double c = 1, d = 1 - (a + b) * x / (a + 1);
    if (std::abs(d) < tiny) d = tiny;
    d = 1 / d;
    double h = d;
    for (int m = 1; m < 10000; ++m) {
        for (int step = 0; step < 2; ++step) {
            double num = step == 0 ? m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m))
                                   : -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1));
            d = 1 + num * d;
            if (std::abs(d) < tiny) d = tiny;
            c = 1 + num / c;
            if (std::abs(c) < tiny) c = tiny;
            d = 1 / d;
            h *= d * c;
        }
        if (std::abs(d * c - 1) < 1e-15) break;
    }
    return front * h;
}

/// Two-sided tail P(|T| >= t) of Student's t with `dof` degrees of freedom.
inline double studentTwoSidedTail(double t, double dof) {
    return regularizedBeta(dof / (dof + t * t), dof / 2, 0.5);
}

/// The t with P(|T| >= t) = level, by bisection on the tail.
inline double studentCritical(double level, double dof) {
    double lo = 0, hi = 1e6;
    for (int i = 0; i < 200; ++i) {
        double mid = 0.5 * (lo + hi);
        (studentTwoSidedTail(mid, dof) > level ? lo : hi) = mid;
    }
    return hi;
}

inline double sidakPerComparison(double familyAlpha, int comparisons) {
    return 1 - std::pow(1 - familyAlpha, 1.0 / std::max(1, comparisons));
}

/// Tolerance for |mean - exact| with `comparisons` comparisons in the test at family level
/// `familyAlpha`, plus float rounding (relative 1e-5) for quantities with no variance.
inline double statisticalTolerance(const MeanAndError& m, double exact, int comparisons = 1,
                                   double familyAlpha = 1e-3) {
    double t = studentCritical(sidakPerComparison(familyAlpha, comparisons), m.count - 1);
    return t * m.standardError + 1e-5 * std::abs(exact);
}

/// Tolerance for |mean(a) - mean(b)| of two independent estimators, each known only through its
/// own seeds: Student-t on the larger standard error of the difference, with the smaller sample's
/// degrees of freedom (a conservative Welch test), at the Sidak level for `comparisons`.
inline double twoSampleTolerance(const MeanAndError& a, const MeanAndError& b, int comparisons = 1,
                                 double familyAlpha = 1e-3) {
    int dof = std::max(1, std::min(a.count, b.count) - 1);
    double t = studentCritical(sidakPerComparison(familyAlpha, comparisons), dof);
    double se = std::sqrt(a.standardError * a.standardError + b.standardError * b.standardError);
    return t * se + 1e-5 * std::max(std::abs(a.mean), std::abs(b.mean));
}

}  // namespace partita::test
