// Tests of the quality metrics (core/image_metrics): RMSE and relMSE of known images, per-layer
// comparison, and the half-split error estimate on synthetic noise of known variance.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "image_metrics.h"

namespace partita {
namespace {

Image filled(int w, int h, float v) {
    Image img(w, h);
    for (float& x : img.rgb) x = v;
    return img;
}

TEST(ImageMetrics, RmseOfAConstantOffsetIsTheOffset) {
    EXPECT_DOUBLE_EQ(rmse(filled(4, 3, 1.5f), filled(4, 3, 1.0f)), 0.5);
    EXPECT_DOUBLE_EQ(rmse(filled(4, 3, 1.0f), filled(4, 3, 1.0f)), 0.0);
}

TEST(ImageMetrics, RmseCountsEveryChannelOfEveryPixel) {
    Image ref = filled(4, 4, 0.0f), x = ref;
    x.set(2, 1, {3.0f, 0.0f, 0.0f});  // one value of 4 * 4 * 3 is off by 3
    EXPECT_DOUBLE_EQ(rmse(x, ref), std::sqrt(9.0 / 48.0));
}

TEST(ImageMetrics, RelMseDividesByTheReferenceSquaredPlusEpsilon) {
    EXPECT_NEAR(relMse(filled(2, 2, 2.0f), filled(2, 2, 1.0f)), 1.0 / (1.0 + 1e-2), 1e-12);
    // On black the epsilon alone divides: (0.1)^2 / 1e-2 = 1.
    EXPECT_NEAR(relMse(filled(2, 2, 0.1f), filled(2, 2, 0.0f)), 1.0, 1e-6);
    // Half the values 3 against 1 (error 4 / 1.01), half exact.
    Image ref = filled(2, 1, 1.0f), x = ref;
    x.set(0, 0, {3.0f, 3.0f, 3.0f});
    EXPECT_NEAR(relMse(x, ref), 0.5 * 4.0 / 1.01, 1e-12);
}

TEST(ImageMetrics, DifferentSizesAreAnErrorNamingBoth) {
    try {
        rmse(Image(4, 3), Image(3, 4));
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("4x3"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("3x4"), std::string::npos) << e.what();
    }
    LayeredImage a{Image(4, 3), {}}, b{Image(8, 6), {}};
    EXPECT_THROW(compareLayers(a, b), std::invalid_argument);
}

TEST(ImageMetrics, CompareLayersCoversCombinedAndTheLayersBothHave) {
    LayeredImage ref{filled(2, 2, 1.0f),
                     {{"LDE", filled(2, 2, 0.5f)}, {"LDDE", filled(2, 2, 0.5f)}}};
    LayeredImage x{filled(2, 2, 1.25f),
                   {{"LDDE", filled(2, 2, 1.0f)}, {"LSDE", filled(2, 2, 9.0f)}}};
    auto errors = compareLayers(x, ref);
    ASSERT_EQ(errors.size(), 2u);
    EXPECT_EQ(errors[0].layer, kCombinedLayerName);
    EXPECT_DOUBLE_EQ(errors[0].rmse, 0.25);
    EXPECT_EQ(errors[1].layer, "LDDE");
    EXPECT_DOUBLE_EQ(errors[1].rmse, 0.5);
    EXPECT_NEAR(errors[1].relMse, 0.25 / (0.25 + 1e-2), 1e-12);
}

TEST(ImageMetrics, MeanOfTwoTakesTheUnionOfLayersWithMissingOnesBlack) {
    LayeredImage a{filled(2, 1, 1.0f), {{"LDE", filled(2, 1, 1.0f)}}};
    LayeredImage b{filled(2, 1, 3.0f), {{"LSDE", filled(2, 1, 2.0f)}, {"LDE", filled(2, 1, 3.0f)}}};
    LayeredImage m = meanOfTwo(a, b);
    EXPECT_FLOAT_EQ(m.combined.at(1, 0).x, 2.0f);
    ASSERT_EQ(m.layers.size(), 2u);
    EXPECT_EQ(m.layers[0].name, "LDE");
    EXPECT_FLOAT_EQ(m.layers[0].image.at(0, 0).y, 2.0f);
    EXPECT_EQ(m.layers[1].name, "LSDE");
    EXPECT_FLOAT_EQ(m.layers[1].image.at(0, 0).z, 1.0f);
}

TEST(ImageMetrics, CompareLayersLeavesOutOther) {
    LayeredImage ref{filled(2, 2, 1.0f),
                     {{"LDE", filled(2, 2, 0.5f)}, {"other", filled(2, 2, 0.5f)}}};
    LayeredImage x{filled(2, 2, 1.0f),
                   {{"other", filled(2, 2, 7.0f)}, {"LDE", filled(2, 2, 0.5f)}}};
    auto errors = compareLayers(x, ref);
    ASSERT_EQ(errors.size(), 2u);
    EXPECT_EQ(errors[1].layer, "LDE");
}

TEST(ImageMetrics, FoldUnsharedLayersMovesTypesOneFilmDroppedIntoOther) {
    // a kept LDE and LSDE (and dropped LDDE into other); b kept LDE and LDDE (dropped LSDE).
    LayeredImage a{
        filled(1, 1, 6.0f),
        {{"LDE", filled(1, 1, 1.0f)}, {"LSDE", filled(1, 1, 2.0f)}, {"other", filled(1, 1, 3.0f)}}};
    LayeredImage b{
        filled(1, 1, 6.0f),
        {{"LDDE", filled(1, 1, 3.0f)}, {"LDE", filled(1, 1, 1.0f)}, {"other", filled(1, 1, 2.0f)}}};
    foldUnsharedLayers(a, b);
    for (const LayeredImage* img : {&a, &b}) {
        ASSERT_EQ(img->layers.size(), 2u);
        EXPECT_FLOAT_EQ(img->layer("LDE")->at(0, 0).x, 1.0f);
        ASSERT_NE(img->layer("other"), nullptr);
        EXPECT_FLOAT_EQ(img->layer("other")->at(0, 0).x, 5.0f);  // LSDE + LDDE
        EXPECT_EQ(img->layers.back().name, "other");
    }
}

TEST(ImageMetrics, FoldUnsharedLayersKeepsCompleteFilmsAsTheyAre) {
    LayeredImage a{filled(1, 1, 1.0f), {{"LDE", filled(1, 1, 1.0f)}}};
    LayeredImage b{filled(1, 1, 2.0f), {{"LDE", filled(1, 1, 1.0f)}, {"LSDE", filled(1, 1, 1.0f)}}};
    foldUnsharedLayers(a, b);  // no "other": LSDE is a type a never sampled
    EXPECT_EQ(a.layers.size(), 1u);
    EXPECT_EQ(b.layers.size(), 2u);
}

/// Two independent "renders": truth mu plus Gaussian noise of standard deviation sigma.
LayeredImage noisy(const Image& mu, double sigma, uint32_t seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, sigma);
    LayeredImage out{mu, {}};
    for (float& v : out.combined.rgb) v = float(v + noise(rng));
    out.layers.push_back({"LDE", out.combined});
    return out;
}

TEST(ImageMetrics, HalfSplitEstimatesTheErrorOfTheMeanFromKnownNoise) {
    const int w = 256, h = 256;
    const double sigma = 0.1;
    Image mu = filled(w, h, 1.0f);
    LayeredImage a = noisy(mu, sigma, 1), b = noisy(mu, sigma, 2);
    auto estimate = halfSplitError(a, b);
    ASSERT_EQ(estimate.size(), 2u);  // combined and LDE
    // The mean of two has standard deviation sigma / sqrt(2) per value. The estimate averages
    // n squared Gaussians: its MSE has relative standard deviation sqrt(2 / n), its RMSE half
    // that; allow 5 of those.
    const double n = 3.0 * w * h;
    const double expected = sigma / std::sqrt(2.0);
    const double tolerance = 5 * expected * std::sqrt(2.0 / n) / 2;
    EXPECT_NEAR(estimate[0].rmse, expected, tolerance);
    EXPECT_NEAR(estimate[1].rmse, expected, tolerance);
    // And it predicts the actual error of the mean against the truth (the same noise enters
    // both, so agreement is closer still than the tolerance).
    double actual = rmse(meanOfTwo(a, b).combined, mu);
    EXPECT_NEAR(estimate[0].rmse, actual, 2 * tolerance);
    // relMSE of the mean against mu: expected^2 / (1 + 1e-2), up to the mean image m standing in
    // for mu in the denominator: a - b and a + b are independent, and E[1 / m^2] for
    // m ~ N(1, sigma^2 / 2) is about 1 + 3 sigma^2 / 2 = 1.015; noise adds sqrt(2 / n) = 0.3%.
    // Allow 5%.
    EXPECT_NEAR(estimate[0].relMse, expected * expected / 1.01, expected * expected * 0.05);
}

TEST(ImageMetrics, HalfSplitOfIdenticalHalvesIsZero) {
    LayeredImage a = noisy(filled(8, 8, 1.0f), 0.1, 7);
    for (const auto& e : halfSplitError(a, a)) {
        EXPECT_EQ(e.rmse, 0.0) << e.layer;
        EXPECT_EQ(e.relMse, 0.0) << e.layer;
    }
}

}  // namespace
}  // namespace partita
