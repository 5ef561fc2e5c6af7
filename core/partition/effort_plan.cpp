#include "partition/effort_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>

namespace partita {

EstimatorChoice parseEstimatorChoice(const std::string& name) {
    if (name == "auto") return EstimatorChoice::Auto;
    if (name == "chains") return EstimatorChoice::Chains;
    if (name == "per-pixel") return EstimatorChoice::PerPixel;
    throw std::invalid_argument("unknown estimators '" + name +
                                "' (expected auto, chains or per-pixel)");
}

namespace {

double chainA(const PartitionEffort& e) {
    return std::max(0.0, e.chainVariance) * std::max(0.0, e.mutationCost);
}

/// sqrt(A_g) of each partition's chains.
std::vector<double> chainRoots(const std::vector<PartitionEffort>& partitions) {
    std::vector<double> out;
    for (const PartitionEffort& e : partitions) out.push_back(std::sqrt(chainA(e)));
    return out;
}

/// F(S) of the header.
double objective(const std::vector<double>& roots, const std::vector<PartitionEffort>& partitions,
                 double pixelCost, const std::vector<bool>& perPixel) {
    double chains = 0, pixels = 0;
    for (size_t g = 0; g < partitions.size(); ++g) {
        if (perPixel[g])
            pixels += std::max(0.0, partitions[g].pixelVariance);
        else
            chains += roots[g];
    }
    return chains + std::sqrt(pixelCost * pixels);
}

/// A per-pixel pilot that saw none of a partition's light cannot vouch for its variance.
bool pixelsMayEstimate(const PartitionEffort& e) { return e.pixelVariance > 0 || !(e.b > 0); }

std::vector<bool> chooseAuto(const std::vector<PartitionEffort>& partitions, double pixelCost) {
    const size_t n = partitions.size();
    const std::vector<double> roots = chainRoots(partitions);
    std::vector<bool> always(n, false);
    for (size_t g = 0; g < n; ++g) always[g] = partitions[g].alwaysPerPixel;
    std::vector<bool> best = always;
    double bestValue = objective(roots, partitions, pixelCost, best);
    auto consider = [&](const std::vector<bool>& candidate) {
        const double value = objective(roots, partitions, pixelCost, candidate);
        if (value < bestValue) {  // strictly: ties keep the chains
            bestValue = value;
            best = candidate;
        }
    };
    std::vector<size_t> eligible;
    for (size_t g = 0; g < n; ++g)
        if (!always[g] && pixelsMayEstimate(partitions[g])) eligible.push_back(g);
    if (eligible.size() <= kExhaustivePartitions) {
        for (uint64_t mask = 1; mask < (uint64_t(1) << eligible.size()); ++mask) {
            std::vector<bool> candidate = always;
            for (size_t j = 0; j < eligible.size(); ++j)
                if ((mask >> j) & 1u) candidate[eligible[j]] = true;
            consider(candidate);
        }
        return best;
    }
    // Ranked by sqrt(A_g) / V_g, largest first (V_g = 0: first of all), ties by index.
    std::stable_sort(eligible.begin(), eligible.end(), [&](size_t a, size_t b) {
        const double va = partitions[a].pixelVariance, vb = partitions[b].pixelVariance;
        return roots[a] * vb > roots[b] * va;
    });
    std::vector<bool> candidate = always;
    for (size_t g : eligible) {
        candidate[g] = true;
        consider(candidate);
    }
    return best;
}

/// Why partition e got its estimator, in words, with the numbers the choice compared: what it
/// adds to F (the header's objective, sqrt of error x cost) with its chains, sqrt(A_g), and as one
/// more per-pixel partition, sqrt(c_pp (V_S + V_g)) - sqrt(c_pp V_S) (V_S the other per-pixel
/// partitions' variance: a BDPT sample estimates them all at once, so a partition's per-pixel
/// cost is only what its variance adds).
std::string reasonOf(const PartitionEffort& e, double pixelCost, bool perPixel,
                     double otherPixelVariance, EstimatorChoice choice) {
    if (e.alwaysPerPixel) return "per pixel: the direct light (direct=per-pixel)";
    if (choice == EstimatorChoice::Chains) return "chains: --estimators chains";
    if (choice == EstimatorChoice::PerPixel) return "per pixel: --estimators per-pixel";
    if (!pixelsMayEstimate(e)) return "chains: the per-pixel pilot saw none of its light";
    const double chains = std::sqrt(chainA(e));
    const double pixels =
        std::sqrt(pixelCost * (otherPixelVariance + std::max(0.0, e.pixelVariance))) -
        std::sqrt(pixelCost * otherPixelVariance);
    char text[200];
    std::snprintf(text, sizeof text, "%s: sqrt(error x cost) +%.3g per pixel, +%.3g with chains",
                  perPixel ? "per pixel" : "chains", pixels, chains);
    return text;
}

}  // namespace

double errorTimesCost(const std::vector<PartitionEffort>& partitions, double pixelCost,
                      const std::vector<bool>& perPixel, const std::vector<double>& chainShare,
                      double pixelShare) {
    double total = 0, pixelVariance = 0;
    for (size_t g = 0; g < partitions.size(); ++g) {
        if (perPixel[g]) {
            pixelVariance += std::max(0.0, partitions[g].pixelVariance);
            continue;
        }
        const double a = chainA(partitions[g]);
        if (a > 0) total += chainShare[g] > 0 ? a / chainShare[g] : INFINITY;
    }
    const double a = pixelCost * pixelVariance;
    if (a > 0) total += pixelShare > 0 ? a / pixelShare : INFINITY;
    return total;
}

EffortPlan planEffort(const std::vector<PartitionEffort>& partitions, double pixelCost,
                      EstimatorChoice choice, bool neyman) {
    const size_t n = partitions.size();
    EffortPlan plan;
    plan.chainShare.assign(n, 0);
    plan.reason.assign(n, "");
    if (!neyman) choice = EstimatorChoice::Chains;
    if (choice == EstimatorChoice::Auto)
        plan.perPixel = chooseAuto(partitions, pixelCost);
    else
        plan.perPixel.assign(n, choice == EstimatorChoice::PerPixel);
    for (size_t g = 0; g < n && neyman; ++g)
        if (partitions[g].alwaysPerPixel) plan.perPixel[g] = true;

    bool anyPixel = false;
    double pixelVariance = 0;
    for (size_t g = 0; g < n; ++g)
        if (plan.perPixel[g]) {
            anyPixel = true;
            pixelVariance += std::max(0.0, partitions[g].pixelVariance);
        }
    if (!neyman) {
        double total = 0;
        for (const PartitionEffort& e : partitions) total += e.p;
        for (size_t g = 0; g < n; ++g) {
            plan.chainShare[g] = total > 0 ? partitions[g].p / total : 1.0 / double(n);
            plan.reason[g] = "chains: Eq. 10, mutations in proportion to P(i)";
        }
    } else {
        // Neyman: shares in proportion to sqrt(A) of each stratum.
        const std::vector<double> roots = chainRoots(partitions);
        const double pixelRoot = std::sqrt(std::max(0.0, pixelCost * pixelVariance));
        double sum = anyPixel ? pixelRoot : 0;
        for (size_t g = 0; g < n; ++g)
            if (!plan.perPixel[g]) sum += roots[g];
        size_t strata = anyPixel ? 1 : 0;
        for (size_t g = 0; g < n; ++g) strata += plan.perPixel[g] ? 0 : 1;
        for (size_t g = 0; g < n; ++g)
            if (!plan.perPixel[g])
                plan.chainShare[g] = sum > 0 ? roots[g] / sum : 1.0 / double(strata);
        if (anyPixel) plan.pixelShare = sum > 0 ? pixelRoot / sum : 1.0 / double(strata);
        for (size_t g = 0; g < n; ++g) {
            const double others =
                pixelVariance - (plan.perPixel[g] ? std::max(0.0, partitions[g].pixelVariance) : 0);
            plan.reason[g] = reasonOf(partitions[g], pixelCost, plan.perPixel[g], others, choice);
        }
    }
    plan.errorTimesCost =
        errorTimesCost(partitions, pixelCost, plan.perPixel, plan.chainShare, plan.pixelShare);
    return plan;
}

double rereadPixelShare(double planShare, double pilotVariance, double variance) {
    const double chains = std::sqrt(pilotVariance) * (1 - planShare) / planShare;
    const double pixels = std::sqrt(std::max(0.0, variance));
    return pixels + chains > 0 ? pixels / (pixels + chains) : planShare;
}

}  // namespace partita
