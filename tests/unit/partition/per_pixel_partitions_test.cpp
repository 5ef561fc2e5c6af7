// The per-pixel partitions (partition/per_pixel_partitions.h) and their pilot: the film keyed by
// sample parity routes every contribution to exactly one half, the halves are the samples'
// two parities, the pilot's k-sample halves give a per-sample variance, and the per-pixel
// estimator follows pixel_estimator (the path tracer only where it can see every light).
#include <gtest/gtest.h>

#include <cfloat>
#include <stdexcept>

#include "partition/effort_pilot.h"
#include "partition/per_pixel_partitions.h"
#include "partitioned_helpers.h"
#include "progress_reporter.h"
#include "render_helpers.h"

namespace partita {
namespace {

using partitioned_test::loadScene;
using partitioned_test::partitionsOf;
using partitioned_test::tinySettings;

std::vector<Partition> allPerPixel(std::vector<Partition> partitions) {
    for (Partition& p : partitions) p.perPixel = true;
    return partitions;
}

TEST(PerPixelPartitions, TheParityHalvesSumToTheImageOfTheSameSamples) {
    const RenderScene scene = loadScene("cornell-glass");
    const std::vector<Partition> partitions = allPerPixel(partitionsOf(scene, 4, 3, 4000));
    ASSERT_GE(partitions.size(), 3u);
    test::TestRenderContext t(scene, tinySettings(1, 5, BudgetKind::SamplesPerPixel));
    RenderObserver quiet;
    for (PerPixelEstimator estimator : {PerPixelEstimator::PathTracer, PerPixelEstimator::Bdpt}) {
        SCOPED_TRACE(perPixelEstimatorName(estimator));
        PerPixelPartitions whole(t.ctx, partitions, estimator);
        PerPixelPartitions halves(t.ctx, partitions, estimator, /*byParity=*/true);
        ProgressReporter progress(quiet, "render", "samples", 0);
        whole.renderPass({0, 8}, progress);
        halves.renderPass({0, 8}, progress);
        const std::vector<Image> all = whole.images(8);
        const Film halvesFilm = halves.takeFilm();
        double lit = 0;
        for (size_t g = 0; g < partitions.size(); ++g) {
            const Image even = parityImage(halvesFilm, partitions.size(), g, false, 4);
            const Image odd = parityImage(halvesFilm, partitions.size(), g, true, 4);
            for (size_t i = 0; i < all[g].rgb.size(); ++i) {
                // Every contribution in exactly one half: the halves' fixed-point sums add up to
                // the whole's exactly (bdpt's splats are summed per sample index, a group that
                // lies in one half), so only float rounding parts them: each of the three sums
                // rounds once to float (relative u = FLT_EPSILON / 2; the scales 1/4 and 1/8 are
                // exact), and even + odd once more: |mean - all| <= 2u (even + odd) / 2 + u all
                // = 2u all for these non-negative values, within 2 FLT_EPSILON all.
                const float mean = (even.rgb[i] + odd.rgb[i]) / 2;
                ASSERT_NEAR(mean, all[g].rgb[i], 2 * FLT_EPSILON * all[g].rgb[i])
                    << "partition " << g << ", component " << i;
                lit += all[g].rgb[i];
            }
        }
        EXPECT_GT(lit, 0.0);
        // The halves are the parities: sample 0 alone is all of the even half's first sample.
        PerPixelPartitions first(t.ctx, partitions, estimator);
        first.renderPass({0, 1}, progress);
        PerPixelPartitions firstHalves(t.ctx, partitions, estimator, true);
        firstHalves.renderPass({0, 1}, progress);
        const std::vector<Image> one = first.images(1);
        const Film firstFilm = firstHalves.takeFilm();
        for (size_t g = 0; g < partitions.size(); ++g) {
            EXPECT_EQ(parityImage(firstFilm, partitions.size(), g, false, 1).rgb, one[g].rgb)
                << "partition " << g;
            for (float v : parityImage(firstFilm, partitions.size(), g, true, 1).rgb)
                ASSERT_EQ(v, 0.0f) << "partition " << g;
        }
    }
}

TEST(PerPixelPartitions, ThePilotsVarianceIsTheSpreadOfIndependentRenders) {
    // V_g / n is the error of partition g's image after n samples, for n = 2k (k samples of each
    // parity, as the pilot's halves: the pilot is then unbiased for it, strata included). Summed
    // over partitions and pixels, the pilots' prediction against the measured variance: each
    // pair of independent n-sample renders gives sum (x1 - x2)^2 / 2, an unbiased estimate of
    // it. 24 pilots and 24 pairs, compared within the tolerance their own spreads give (a
    // two-sample t test; with fewer, a V off by the factor k would pass). The path tracer's
    // k = 4 pilot and BDPT's k = 1.
    const RenderScene scene = loadScene("cornell");
    const std::vector<Partition> partitions = allPerPixel(partitionsOf(scene, 2, 3, 4000));
    RenderObserver quiet;
    for (const auto& [estimatorOfPair, kOfPair] :
         {std::pair{PerPixelEstimator::PathTracer, uint64_t(4)},
          std::pair{PerPixelEstimator::Bdpt, uint64_t(1)}}) {
        // Plain copies: clang 14 does not let a lambda capture a structured binding.
        const PerPixelEstimator estimator = estimatorOfPair;
        const uint64_t k = kOfPair;
        SCOPED_TRACE(perPixelEstimatorName(estimator));
        const uint64_t n = 2 * k;
        std::vector<double> predicted;
        for (int p = 0; p < 24; ++p) {
            test::TestRenderContext t(scene, tinySettings(1, 100 + p, BudgetKind::SamplesPerPixel));
            ProgressReporter progress(quiet, "pilot", "samples", 0);
            const PerPixelPilot pilot =
                runPerPixelPilot(t.ctx, partitions, estimator, kPerPixelPilotSample, progress, k);
            double sum = 0;
            for (double v : pilot.variance) sum += v / double(n);
            predicted.push_back(sum);
        }
        auto render = [&](uint64_t seed) {
            test::TestRenderContext t(scene, tinySettings(1, seed, BudgetKind::SamplesPerPixel));
            PerPixelPartitions r(t.ctx, partitions, estimator);
            ProgressReporter progress(quiet, "render", "samples", 0);
            r.renderPass({0, n}, progress);
            return r.images(n);
        };
        std::vector<double> measured;
        for (uint64_t pair = 0; pair < 24; ++pair) {
            const std::vector<Image> a = render(200 + 2 * pair), b = render(201 + 2 * pair);
            double sum = 0;
            for (size_t g = 0; g < partitions.size(); ++g)
                for (int y = 0; y < a[g].height; ++y)
                    for (int x = 0; x < a[g].width; ++x) {
                        const double d = luminance(a[g].at(x, y)) - luminance(b[g].at(x, y));
                        sum += d * d / 2;
                    }
            measured.push_back(sum);
        }
        const test::MeanAndError p = test::meanAndError(predicted),
                                 m = test::meanAndError(measured);
        ASSERT_GT(m.mean, 0.0);
        EXPECT_GT(p.mean, 0.0) << "halves that are not independent would give V near 0";
        EXPECT_NEAR(p.mean, m.mean, test::twoSampleTolerance(p, m, 2))
            << "predicted " << p.mean << " +- " << p.standardError << ", measured " << m.mean
            << " +- " << m.standardError;
    }
}

TEST(PixelEstimator, TheRuleTakesThePathTracerOnlyWhereItSeesEveryLight) {
    auto estimatorOf = [](const std::string& scene, const std::string& asked) {
        RenderSettings st = tinySettings(2, 1, BudgetKind::MutationsPerPixel);
        st.parameters.set("bootstrap", 4000)
            .set("estimators", std::string("per-pixel"))
            .set("pixel_estimator", asked);
        return test::renderWith(loadScene(scene), "partitioned", st)
            .stats.labels["per_pixel_estimator"];
    };
    EXPECT_EQ(estimatorOf("cornell", "auto"), "pt");
    EXPECT_EQ(estimatorOf("cornell-point", "auto"), "bdpt") << "point lights";
    EXPECT_EQ(estimatorOf("cornell", "bdpt"), "bdpt");
    EXPECT_THROW(estimatorOf("cornell-point", "pt"), std::invalid_argument);
}

}  // namespace
}  // namespace partita
