// The per-pixel partitions (partition/per_pixel_partitions.h) and their pilot: the film keyed by
// sample parity routes every contribution to exactly one half, the halves are the samples'
// two parities, the pilot's k-sample halves give a per-sample variance, and the per-pixel
// estimator follows pixel_estimator (the path tracer only where it can see every light).
#include <gtest/gtest.h>

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
                // Every contribution in exactly one half: (even + odd) / 2 is the whole image
                // (each resolved from exact sums, so up to float rounding).
                const float mean = (even.rgb[i] + odd.rgb[i]) / 2;
                ASSERT_NEAR(mean, all[g].rgb[i], 1e-5f * std::max(1.0f, all[g].rgb[i]))
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
    // V_g / n is the error of partition g's image after n samples: over independent seeds, the
    // sum over partitions and pixels of the luminance's variance at n = 8 samples, against the
    // pilots' sum of V_g / 8, for the path tracer's k = 4 pilot and BDPT's k = 1 (cornell: no
    // edge inside a pixel that the strata would gain on much). A factor-of-two band: each pilot
    // is one draw of a sum over 192 pixels, and 6 of them are averaged (the test catches a V
    // off by k, or halves that are not independent, which would give V near 0).
    const RenderScene scene = loadScene("cornell");
    const std::vector<Partition> partitions = allPerPixel(partitionsOf(scene, 2, 3, 4000));
    RenderObserver quiet;
    for (const auto& [estimator, k] : {std::pair{PerPixelEstimator::PathTracer, uint64_t(4)},
                                       std::pair{PerPixelEstimator::Bdpt, uint64_t(1)}}) {
        SCOPED_TRACE(perPixelEstimatorName(estimator));
        double predicted = 0;
        const int pilots = 6;
        for (int p = 0; p < pilots; ++p) {
            test::TestRenderContext t(scene, tinySettings(1, 100 + p, BudgetKind::SamplesPerPixel));
            ProgressReporter progress(quiet, "pilot", "samples", 0);
            const PerPixelPilot pilot =
                runPerPixelPilot(t.ctx, partitions, estimator, kPerPixelPilotSample, progress, k);
            for (double v : pilot.variance) predicted += v / pilots;
        }
        const int seeds = 24;
        const uint64_t n = 8;
        std::vector<std::vector<Image>> renders;  // per seed, per partition
        for (int s = 0; s < seeds; ++s) {
            test::TestRenderContext t(scene, tinySettings(1, 200 + s, BudgetKind::SamplesPerPixel));
            PerPixelPartitions r(t.ctx, partitions, estimator);
            ProgressReporter progress(quiet, "render", "samples", 0);
            r.renderPass({0, n}, progress);
            renders.push_back(r.images(n));
        }
        double measured = 0;
        for (size_t g = 0; g < partitions.size(); ++g) {
            const Image& shape = renders[0][g];
            for (int y = 0; y < shape.height; ++y)
                for (int x = 0; x < shape.width; ++x) {
                    double mean = 0, square = 0;
                    for (const auto& seed : renders) {
                        const double l = luminance(seed[g].at(x, y));
                        mean += l / seeds;
                        square += l * l / seeds;
                    }
                    measured += (square - mean * mean) * seeds / (seeds - 1);
                }
        }
        ASSERT_GT(measured, 0.0);
        const double ratio = predicted / double(n) / measured;
        EXPECT_GT(ratio, 0.5) << "predicted " << predicted / double(n) << ", measured " << measured;
        EXPECT_LT(ratio, 2.0) << "predicted " << predicted / double(n) << ", measured " << measured;
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
