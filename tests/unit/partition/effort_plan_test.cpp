// The effort plan (partition/effort_plan.h): on a synthetic problem with known per-partition
// variances and costs, the error measured over many independent repetitions matches the
// formula's prediction (errorTimesCost / T), for the Neyman shares and for Eq. 10's; Neyman's
// measured error is the lower; the choice sends a partition per pixel or to chains as its
// numbers say, and keeps chains where the per-pixel pilot saw nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "half_split_error.h"
#include "partition/effort_plan.h"
#include "rng.h"
#include "statistics.h"

namespace partita {
namespace {

/// One estimate's squared error, drawing the samples: partition g with chains gets
/// n_g = share_g T / c_g samples of variance v_g, the per-pixel partitions n = pixelShare T / c_pp
/// samples each of variance V_g (independent). Samples are exponential (shifted to mean 0,
/// scaled to the variance), not Gaussian: the 1 / n law is what is tested, not the shape.
double squaredError(const std::vector<PartitionEffort>& parts, double pixelCost,
                    const EffortPlan& plan, double total, Rng& rng) {
    auto meanError = [&](double variance, uint64_t n) {
        double sum = 0;
        for (uint64_t i = 0; i < n; ++i) sum += -std::log(1.0 - double(rng.nextFloat())) - 1.0;
        return std::sqrt(variance) * sum / double(n);
    };
    const uint64_t spp = uint64_t(std::llround(plan.pixelShare * total / pixelCost));
    double error = 0;
    for (size_t g = 0; g < parts.size(); ++g) {
        const uint64_t n =
            plan.perPixel[g]
                ? spp
                : uint64_t(std::llround(plan.chainShare[g] * total / parts[g].mutationCost));
        const double e =
            meanError(plan.perPixel[g] ? parts[g].pixelVariance : parts[g].chainVariance, n);
        error += e * e;  // the partitions' errors are independent: their squares add
    }
    return error;
}

std::vector<PartitionEffort> syntheticPartitions() {
    // p, b, v_g, c_g, V_g: two that chains do well, one a per-pixel estimator does well, and
    // one per-pixel-friendly partition that is cheap to add to the shared samples.
    return {{0.5, 1.0, 4.0, 1.0, 400.0},
            {0.3, 1.0, 1.0, 2.0, 300.0},
            {0.1, 1.0, 900.0, 1.0, 1.0},
            {0.1, 1.0, 400.0, 1.0, 2.0}};
}

/// The mean squared error over `reps` repetitions against the prediction, within the
/// tolerance its spread gives (`comparisons` in the test).
void expectPrediction(const std::vector<PartitionEffort>& parts, double pixelCost,
                      const EffortPlan& plan, double total, uint64_t seed, int comparisons,
                      double* measured = nullptr) {
    Rng rng(seed, 0);
    std::vector<double> errors;
    for (int r = 0; r < 4000; ++r)
        errors.push_back(squaredError(parts, pixelCost, plan, total, rng));
    const test::MeanAndError m = test::meanAndError(errors);
    const double predicted = plan.errorTimesCost / total;
    EXPECT_NEAR(m.mean, predicted, test::statisticalTolerance(m, predicted, comparisons))
        << "measured " << m.mean << " +- " << m.standardError << ", predicted " << predicted;
    if (measured) *measured = m.mean;
}

TEST(EffortPlan, MeasuredErrorMatchesThePredictionAndNeymanBeatsEq10) {
    const std::vector<PartitionEffort> parts = syntheticPartitions();
    const double pixelCost = 1.5, total = 400;
    const EffortPlan neyman = planEffort(parts, pixelCost, EstimatorChoice::Auto, true);
    const EffortPlan chainsNeyman = planEffort(parts, pixelCost, EstimatorChoice::Chains, true);
    const EffortPlan eq10 = planEffort(parts, pixelCost, EstimatorChoice::Auto, false);
    // The shares spend the whole cost.
    for (const EffortPlan* plan : {&neyman, &chainsNeyman, &eq10}) {
        double sum = plan->pixelShare;
        for (double s : plan->chainShare) sum += s;
        EXPECT_NEAR(sum, 1.0, 1e-12);
    }
    double a = 0, b = 0, c = 0;
    expectPrediction(parts, pixelCost, neyman, total, 1, 3, &a);
    expectPrediction(parts, pixelCost, chainsNeyman, total, 2, 3, &b);
    expectPrediction(parts, pixelCost, eq10, total, 3, 3, &c);
    // Auto sends the per-pixel-friendly partitions per pixel; Eq. 10 keeps chains everywhere.
    EXPECT_EQ(neyman.perPixel, (std::vector<bool>{false, false, true, true}));
    EXPECT_EQ(eq10.perPixel, std::vector<bool>(4, false));
    // Predicted ratios far beyond the spread: auto < chains with Neyman < Eq. 10.
    EXPECT_LT(neyman.errorTimesCost, 0.5 * chainsNeyman.errorTimesCost);
    EXPECT_LT(chainsNeyman.errorTimesCost, eq10.errorTimesCost);
    EXPECT_LT(a, b);
    EXPECT_LT(b, c);
}

TEST(EffortPlan, AutoIsTheBestSubsetAndKeepsChainsWhereThePilotSawNothing) {
    std::vector<PartitionEffort> parts = syntheticPartitions();
    const double pixelCost = 1.5;
    const EffortPlan plan = planEffort(parts, pixelCost, EstimatorChoice::Auto, true);
    // No other assignment of estimators has a lower optimum.
    for (uint32_t mask = 0; mask < 16; ++mask) {
        std::vector<bool> perPixel(4);
        for (size_t g = 0; g < 4; ++g) perPixel[g] = (mask >> g) & 1u;
        double roots = 0, pixels = 0;
        for (size_t g = 0; g < 4; ++g)
            if (perPixel[g])
                pixels += parts[g].pixelVariance;
            else
                roots += std::sqrt(parts[g].chainVariance * parts[g].mutationCost);
        roots += std::sqrt(pixelCost * pixels);
        EXPECT_LE(plan.errorTimesCost, roots * roots * (1 + 1e-12)) << mask;
    }
    // A partition whose light no pilot sample reached keeps its chains, however cheap.
    parts[2].pixelVariance = 0;
    const EffortPlan blind = planEffort(parts, pixelCost, EstimatorChoice::Auto, true);
    EXPECT_FALSE(blind.perPixel[2]);
    EXPECT_NE(blind.reason[2].find("saw none"), std::string::npos) << blind.reason[2];
    // Forced choices.
    EXPECT_EQ(planEffort(parts, pixelCost, EstimatorChoice::PerPixel, true).perPixel,
              std::vector<bool>(4, true));
    EXPECT_EQ(planEffort(parts, pixelCost, EstimatorChoice::Chains, true).perPixel,
              std::vector<bool>(4, false));
    EXPECT_THROW(parseEstimatorChoice("bdpt"), std::invalid_argument);
}

TEST(EffortPlan, TheDirectLightIsPerPixelWhateverItsChainsWouldGive) {
    std::vector<PartitionEffort> parts = syntheticPartitions();
    const double pixelCost = 1.5;
    // Partition 0's chains made cheap and precise: auto would keep them ...
    parts[0].chainVariance = 1e-6;
    ASSERT_FALSE(planEffort(parts, pixelCost, EstimatorChoice::Auto, true).perPixel[0]);
    // ... unless it is the direct light: then per pixel, and the rest is still the best subset.
    parts[0].alwaysPerPixel = true;
    const EffortPlan plan = planEffort(parts, pixelCost, EstimatorChoice::Auto, true);
    EXPECT_TRUE(plan.perPixel[0]);
    EXPECT_GT(plan.pixelShare, 0.0);
    EXPECT_NE(plan.reason[0].find("direct"), std::string::npos) << plan.reason[0];
    for (uint32_t mask = 0; mask < 8; ++mask) {
        std::vector<bool> perPixel{true, bool(mask & 1u), bool(mask & 2u), bool(mask & 4u)};
        double roots = 0, pixels = 0;
        for (size_t g = 0; g < 4; ++g)
            if (perPixel[g])
                pixels += parts[g].pixelVariance;
            else
                roots += std::sqrt(parts[g].chainVariance * parts[g].mutationCost);
        roots += std::sqrt(pixelCost * pixels);
        EXPECT_LE(plan.errorTimesCost, roots * roots * (1 + 1e-12)) << mask;
    }
    // Even when every other partition is forced to chains by the choice.
    EXPECT_EQ(planEffort(parts, pixelCost, EstimatorChoice::Chains, true).perPixel,
              (std::vector<bool>{true, false, false, false}));
}

TEST(EffortPlan, TheRereadShareIsThePlansWithTheNewVariance) {
    // The per-pixel phase's re-read share equals the share planEffort gives with the per-pixel
    // stratum's variance scaled (the estimators kept: partitions 0 and 1 per pixel here).
    std::vector<PartitionEffort> parts = syntheticPartitions();
    const double pixelCost = 1.5;
    parts[0].alwaysPerPixel = parts[1].alwaysPerPixel = true;
    for (PartitionEffort& p : parts) p.pixelVariance = p.alwaysPerPixel ? p.pixelVariance : 0;
    const EffortPlan plan = planEffort(parts, pixelCost, EstimatorChoice::Chains, true);
    ASSERT_GT(plan.pixelShare, 0.0);
    ASSERT_LT(plan.pixelShare, 1.0);
    const double v = parts[0].pixelVariance + parts[1].pixelVariance;
    EXPECT_NEAR(rereadPixelShare(plan.pixelShare, v, v), plan.pixelShare, 1e-12);
    for (double scale : {0.01, 0.5, 4.0, 1e4}) {
        std::vector<PartitionEffort> scaled = parts;
        scaled[0].pixelVariance *= scale;
        scaled[1].pixelVariance *= scale;
        const EffortPlan again = planEffort(scaled, pixelCost, EstimatorChoice::Chains, true);
        EXPECT_NEAR(rereadPixelShare(plan.pixelShare, v, v * scale), again.pixelShare, 1e-9)
            << scale;
    }
    // Pooled by sample counts; the pilot's alone before the phase's own has two samples.
    EXPECT_EQ(pooledVariance(3.0, 8, 100.0, 1), 3.0);
    EXPECT_EQ(pooledVariance(3.0, 8, 0.0, 10), 3.0);
    EXPECT_NEAR(pooledVariance(3.0, 8, 100.0, 24), (8 * 3.0 + 24 * 100.0) / 32, 1e-12);
}

TEST(EffortPlan, ManyPartitionsUseTheRankedPrefixes) {
    // More partitions than the exhaustive search takes: the ranked prefixes, never worse than
    // all chains or all per pixel.
    std::vector<PartitionEffort> parts;
    Rng rng(5, 0);
    for (int g = 0; g < 24; ++g)
        parts.push_back({1.0 / 24, 1.0, 1 + 100.0 * rng.nextFloat(), 1 + rng.nextFloat(),
                         1 + 100.0 * rng.nextFloat()});
    const double pixelCost = 3;
    const double best = planEffort(parts, pixelCost, EstimatorChoice::Auto, true).errorTimesCost;
    EXPECT_LE(best, planEffort(parts, pixelCost, EstimatorChoice::Chains, true).errorTimesCost);
    EXPECT_LE(best, planEffort(parts, pixelCost, EstimatorChoice::PerPixel, true).errorTimesCost);
}

}  // namespace
}  // namespace partita
