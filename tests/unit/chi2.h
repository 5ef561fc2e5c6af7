// Chi-square goodness-of-fit test for direction samplers (BSDFs, lights, phase functions).
//
// The sphere of directions is cut into a (theta, phi) grid, theta in [0, pi] from +z, phi in
// [0, 2 pi). A sampler is run N times and the directions binned; the expected count of a bin is
// N times the integral of the claimed solid-angle pdf over the bin, computed by adaptive
// Gauss-Legendre cubature in (theta, phi) with the sin(theta) Jacobian. Samplers may fail (return
// nullopt, e.g. a GGX reflection below the horizon); failures form one more cell whose expected
// count is N (1 - integral of the pdf), so a pdf that claims too much or too little mass is caught
// too.
//
// Pearson's statistic needs every expected count to be large enough for its chi-square
// approximation (the usual rule: >= 5). Cells below that are pooled, smallest first, into one
// cell; if the pool is still below 5 it is merged with the smallest regular cell. A cell that
// received samples but whose expected count is exactly zero is a support violation: the sampler
// produced directions where the pdf says it never does, and the test fails outright.
//
// The p-value is the chi-square survival function, Q(dof / 2, statistic / 2), Q being the
// regularised upper incomplete gamma function. A test run under a correct sampler yields a
// uniform p-value, so rejecting at p < alpha has false-alarm probability alpha per test. A suite
// runs many tests; to keep the probability that ANY correct test fails at alpha = 1e-3, each test
// uses the Sidak-corrected level 1 - (1 - alpha)^(1/m) (~ alpha / m) for m tests. The seeds are
// fixed, so a run is deterministic: the correction bounds the chance that a correct
// implementation is flagged by an unlucky choice of seeds, while a real error (wrong Jacobian,
// wrong branch probability) gives p-values far below any such level at these sample counts.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "math/vec.h"
#include "rng.h"

namespace partita::test {

/// Regularised lower incomplete gamma P(a, x) = gamma(a, x) / Gamma(a) by its power series,
/// for x < a + 1 where the series converges quickly.
inline double gammaPSeries(double a, double x) {
    double term = 1 / a, sum = term;
    for (int n = 1; n < 100000; ++n) {
        term *= x / (a + n);
        sum += term;
        if (std::abs(term) < std::abs(sum) * 1e-16) break;
    }
    return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

/// Regularised upper incomplete gamma Q(a, x) by Legendre's continued fraction, evaluated with
/// the modified Lentz method, for x >= a + 1.
inline double gammaQContinuedFraction(double a, double x) {
    const double tiny = 1e-300;
    double b = x + 1 - a;
    double c = 1 / tiny;
    double d = 1 / b;
    double h = d;
    for (int i = 1; i < 100000; ++i) {
        double an = -i * (i - a);
        b += 2;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1 / d;
        double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1) < 1e-16) break;
    }
    return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

/// Regularised upper incomplete gamma function Q(a, x) = 1 - P(a, x).
inline double regularizedGammaQ(double a, double x) {
    if (x <= 0) return 1;
    if (x < a + 1) return 1 - gammaPSeries(a, x);
    return gammaQContinuedFraction(a, x);
}

/// P(X >= statistic) for X chi-square distributed with `dof` degrees of freedom.
inline double chi2SurvivalProbability(double statistic, int dof) {
    return regularizedGammaQ(0.5 * dof, 0.5 * statistic);
}

/// Per-test significance level that keeps the family-wise false-alarm rate at `alpha` over
/// `testCount` independent tests (Sidak).
inline double sidakLevel(double alpha, int testCount) {
    return 1 - std::pow(1 - alpha, 1.0 / std::max(1, testCount));
}

/// Pearson's chi-square test of counts against probabilities times n, over the cells with a
/// non-zero probability.
struct Pearson {
    double statistic = 0, pValue = 0, minExpected = 0;
    int dof = 0;
    std::string describe() const {
        std::ostringstream os;
        os << "chi2 = " << statistic << ", dof = " << dof << ", p = " << pValue
           << ", smallest expected count = " << minExpected;
        return os.str();
    }
};

template <typename Counts, typename Probabilities>
Pearson pearson(const Counts& observed, const Probabilities& probability, double n) {
    Pearson r;
    r.minExpected = n;
    int cells = 0;
    for (size_t i = 0; i < observed.size(); ++i) {
        if (probability[i] == 0) continue;
        double e = n * probability[i];
        r.statistic += (observed[i] - e) * (observed[i] - e) / e;
        r.minExpected = std::min(r.minExpected, e);
        ++cells;
    }
    r.dof = cells - 1;
    r.pValue = chi2SurvivalProbability(r.statistic, r.dof);
    return r;
}

struct Chi2Options {
    int thetaBins = 16;
    int phiBins = 32;
    int sampleCount = 200000;
    double integrationTolerance = 0.05;  // quadrature error per bin, in Poisson sigmas
    int maxIntegrationDepth = 7;
    double minExpected = 5;
};

struct Chi2Result {
    double statistic = 0;
    int dof = 0;
    double pValue = 0;
    double pdfIntegral = 0;      // integral of the pdf over the sphere
    long failures = 0;           // sampler returned nothing
    long supportViolations = 0;  // samples in cells with zero expected count
    int pooledCells = 0;         // cells merged into the low-count pool
    std::string describe() const {
        std::ostringstream os;
        os << "chi2 = " << statistic << ", dof = " << dof << ", p = " << pValue
           << ", pdf integral = " << pdfIntegral << ", failures = " << failures
           << ", support violations = " << supportViolations << ", pooled cells = " << pooledCells;
        return os.str();
    }
};

using DirectionSampler = std::function<std::optional<Vec3f>(Rng&)>;
using DirectionPdf = std::function<double(Vec3f)>;

inline Vec3f sphericalDirection(double theta, double phi) {
    double s = std::sin(theta);
    return Vec3f(float(s * std::cos(phi)), float(s * std::sin(phi)), float(std::cos(theta)));
}

/// 4x4-point Gauss-Legendre cubature of pdf(theta, phi) sin(theta) over a (theta, phi) cell.
inline double gaussCell(const DirectionPdf& pdf, double t0, double t1, double p0, double p1) {
    static const double x[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                0.8611363115940526};
    static const double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                0.3478548451374538};
    double tc = 0.5 * (t0 + t1), th = 0.5 * (t1 - t0), pc = 0.5 * (p0 + p1), ph = 0.5 * (p1 - p0);
    double sum = 0;
    for (int i = 0; i < 4; ++i) {
        double theta = tc + th * x[i];
        double s = std::sin(theta);
        for (int j = 0; j < 4; ++j)
            sum += w[i] * w[j] * s * pdf(sphericalDirection(theta, pc + ph * x[j]));
    }
    return sum * th * ph;
}

/// Adaptive cubature: compare the cell's Gauss estimate with the sum over its four quarters and
/// recurse where they disagree by more than the cell's share of the tolerance. The tolerance is
/// statistical: a bin with expected count E must be integrated to well within its Poisson
/// error sqrt(E), here to integrationTolerance * sqrt(E) counts, so that quadrature error never
/// looks like a sampling mismatch. BSDF pdfs have peaks (low roughness) and jumps inside bins
/// (a microfacet normal reaching the horizon cuts a transmission lobe off); a fixed rule
/// misjudges both.
inline double integrateCell(const DirectionPdf& pdf, double t0, double t1, double p0, double p1,
                            const Chi2Options& opts, int depth, double whole = -1,
                            double share = 1) {
    if (whole < 0) whole = gaussCell(pdf, t0, t1, p0, p1);
    double tm = 0.5 * (t0 + t1), pm = 0.5 * (p0 + p1);
    double q[4] = {gaussCell(pdf, t0, tm, p0, pm), gaussCell(pdf, tm, t1, p0, pm),
                   gaussCell(pdf, t0, tm, pm, p1), gaussCell(pdf, tm, t1, pm, p1)};
    double refined = q[0] + q[1] + q[2] + q[3];
    double n = opts.sampleCount;
    double tolerance =
        opts.integrationTolerance * std::sqrt(std::max(1.0, refined * n)) * share / n;
    if (std::abs(refined - whole) <= tolerance || depth >= opts.maxIntegrationDepth) return refined;
    return integrateCell(pdf, t0, tm, p0, pm, opts, depth + 1, q[0], share / 2) +
           integrateCell(pdf, tm, t1, p0, pm, opts, depth + 1, q[1], share / 2) +
           integrateCell(pdf, t0, tm, pm, p1, opts, depth + 1, q[2], share / 2) +
           integrateCell(pdf, tm, t1, pm, p1, opts, depth + 1, q[3], share / 2);
}

/// Run the test: draw opts.sampleCount directions with `sample`, compare against `pdf`.
inline Chi2Result chi2Test(const DirectionSampler& sample, const DirectionPdf& pdf, Rng& rng,
                           const Chi2Options& opts = {}) {
    const int nt = opts.thetaBins, np = opts.phiBins;
    const double dTheta = kPi / nt, dPhi = 2 * kPi / np;
    Chi2Result result;

    // Observed counts.
    std::vector<double> observed(size_t(nt * np), 0.0);
    for (int i = 0; i < opts.sampleCount; ++i) {
        std::optional<Vec3f> w = sample(rng);
        if (!w) {
            ++result.failures;
            continue;
        }
        double z = clamp(double(w->z) / length(*w), -1.0, 1.0);
        double theta = std::acos(z);
        double phi = std::atan2(double(w->y), double(w->x));
        if (phi < 0) phi += 2 * kPi;
        int ti = std::min(nt - 1, int(theta / dTheta));
        int pi = std::min(np - 1, int(phi / dPhi));
        observed[size_t(ti * np + pi)] += 1;
    }

    // Expected counts: adaptive cubature of pdf(theta, phi) sin(theta) over each bin (see
    // integrateCell). Only interior nodes are used, so a pdf that jumps at a bin edge (the
    // horizon, where reflection meets transmission) is integrated from the bin's own side.
    std::vector<double> expected(size_t(nt * np), 0.0);
    for (int ti = 0; ti < nt; ++ti)
        for (int pi = 0; pi < np; ++pi) {
            double integral = integrateCell(pdf, ti * dTheta, (ti + 1) * dTheta, pi * dPhi,
                                            (pi + 1) * dPhi, opts, 0);
            result.pdfIntegral += integral;
            expected[size_t(ti * np + pi)] = integral * opts.sampleCount;
        }
    observed.push_back(double(result.failures));
    expected.push_back(std::max(0.0, 1 - result.pdfIntegral) * opts.sampleCount);

    // Pool low-expectation cells, smallest first.
    std::vector<size_t> order(observed.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return expected[a] < expected[b]; });
    double poolObserved = 0, poolExpected = 0;
    std::vector<std::pair<double, double>> cells;  // (observed, expected)
    for (size_t k : order) {
        if (expected[k] == 0) {
            result.supportViolations += long(observed[k]);
            continue;
        }
        if (expected[k] < opts.minExpected) {
            poolObserved += observed[k];
            poolExpected += expected[k];
            ++result.pooledCells;
        } else {
            cells.emplace_back(observed[k], expected[k]);
        }
    }
    if (poolExpected > 0) {
        if (poolExpected < opts.minExpected && !cells.empty()) {
            // cells are in increasing order of expectation: merge into the smallest.
            cells.front().first += poolObserved;
            cells.front().second += poolExpected;
        } else {
            cells.emplace_back(poolObserved, poolExpected);
        }
    }
    for (auto [o, e] : cells) result.statistic += (o - e) * (o - e) / e;
    result.dof = int(cells.size()) - 1;
    if (result.supportViolations > 0 || result.dof < 1) {
        result.pValue = 0;
        return result;
    }
    result.pValue = chi2SurvivalProbability(result.statistic, result.dof);
    return result;
}

}  // namespace partita::test
