// Chi-square tests of light sampling and of the sampling routines lights and cameras use.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "alias_table.h"
#include "chi2.h"
#include "render_scene.h"
#include "sampling.h"
#include "scene_builders.h"

namespace partita {
namespace {

// Six chi-square tests in this file share a family-wise false-alarm level of 1e-3.
constexpr double kFamilyAlpha = 1e-3;
constexpr int kChi2Tests = 6;

/// Pearson chi-square p-value of observed counts against expected probabilities (cells with
/// expected count below 5 pooled).
double discreteChi2PValue(const std::vector<double>& observed,
                          const std::vector<double>& probability, double n) {
    double statistic = 0, pooledObserved = 0, pooledExpected = 0;
    int cells = 0;
    for (size_t i = 0; i < observed.size(); ++i) {
        double e = probability[i] * n;
        if (e < 5) {
            pooledObserved += observed[i];
            pooledExpected += e;
            continue;
        }
        statistic += sqr(float(observed[i] - e)) / e;
        ++cells;
    }
    if (pooledExpected > 0) {
        statistic +=
            (pooledObserved - pooledExpected) * (pooledObserved - pooledExpected) / pooledExpected;
        ++cells;
    }
    return test::chi2SurvivalProbability(statistic, cells - 1);
}

/// One emissive triangle seen from a point below it at an angle.
SceneData triangleLightScene(bool twoSided) {
    SceneData s;
    s.materials = {test::lambertMaterial(Rgb(0.0f), Rgb(3.0f), twoSided)};
    TriangleMesh tri;
    tri.positions = {{-0.5f, 1, -0.3f}, {0.8f, 1.3f, 0.1f}, {-0.1f, 0.9f, 0.9f}};
    Vec3f n =
        normalize(cross(tri.positions[1] - tri.positions[0], tri.positions[2] - tri.positions[0]));
    if (n.y > 0) std::swap(tri.positions[1], tri.positions[2]);  // face down, towards the reference
    n = normalize(cross(tri.positions[1] - tri.positions[0], tri.positions[2] - tri.positions[0]));
    tri.normals = {n, n, n};
    tri.indices = {0, 1, 2};
    tri.material = 0;
    s.meshes.push_back(tri);
    return s;
}

TEST(LightSampling, AreaLightDirectionsFollowTheirSolidAnglePdf) {
    RenderScene scene(triangleLightScene(false));
    ASSERT_EQ(scene.lights().size(), 1u);
    const Vec3f ref(0.2f, 0.1f, 0.3f);
    test::DirectionSampler sampler = [&](Rng& rng) -> std::optional<Vec3f> {
        auto s = scene.sampleLight(0, ref, {rng.nextFloat(), rng.nextFloat()});
        if (!s) return std::nullopt;
        return s->wi;
    };
    // The pdf a direction has is found independently of the sampler: trace it with Embree and
    // convert the area density 1/A of the point it hits to solid angle.
    test::DirectionPdf pdf = [&](Vec3f w) -> double {
        auto hit = scene.intersect(Ray{ref, w, kInf});
        if (!hit || scene.areaLightIndex(*hit) != 0) return 0.0;
        return scene.areaLightPdf(0, ref, *hit);
    };
    Rng rng(42, 7);
    test::Chi2Options opts;
    opts.sampleCount = 100000;
    auto result = test::chi2Test(sampler, pdf, rng, opts);
    EXPECT_EQ(result.supportViolations, 0) << result.describe();
    EXPECT_GE(result.pValue, test::sidakLevel(kFamilyAlpha, kChi2Tests)) << result.describe();

    // Power check: the same test must reject a pdf that is off by the cosine at the light
    // (the classic area-to-solid-angle mistake).
    test::DirectionPdf wrongPdf = [&](Vec3f w) -> double {
        auto hit = scene.intersect(Ray{ref, w, kInf});
        if (!hit || scene.areaLightIndex(*hit) != 0) return 0.0;
        return scene.areaLightPdf(0, ref, *hit) * absDot(hit->ng, w);
    };
    Rng rng2(42, 7);
    EXPECT_LT(test::chi2Test(sampler, wrongPdf, rng2, opts).pValue, 1e-6);
}

TEST(LightSampling, OneSidedLightDoesNotSampleItsBack) {
    RenderScene scene(triangleLightScene(false));
    Rng rng(1, 1);
    for (int i = 0; i < 1000; ++i)
        EXPECT_FALSE(
            scene.sampleLight(0, Vec3f(0.2f, 2.0f, 0.3f), {rng.nextFloat(), rng.nextFloat()}));
    RenderScene twoSided(triangleLightScene(true));
    EXPECT_TRUE(twoSided.sampleLight(0, Vec3f(0.2f, 2.0f, 0.3f), {0.3f, 0.3f}));
}

TEST(LightSampling, LightSelectionFollowsPower) {
    SceneData s = triangleLightScene(false);
    for (float intensity : {1.0f, 4.0f, 0.25f}) {
        PunctualLightDesc p;
        p.intensity = intensity;
        p.position = {0, 3, 0};
        s.lights.push_back(p);
    }
    RenderScene scene(std::move(s));
    const auto& dist = scene.lightSelection();
    ASSERT_EQ(dist.size(), 4u);
    std::vector<double> expected, observed(4, 0);
    double total = 0;
    for (const Light& l : scene.lights()) total += lightPower(l);
    for (const Light& l : scene.lights()) expected.push_back(lightPower(l) / total);
    for (size_t i = 0; i < 4; ++i) EXPECT_NEAR(dist.pmf(uint32_t(i)), expected[i], 1e-6);
    Rng rng(5, 5);
    const int n = 200000;
    for (int i = 0; i < n; ++i) observed[dist.sample(rng.nextFloat())] += 1;
    EXPECT_GE(discreteChi2PValue(observed, expected, n),
              test::sidakLevel(kFamilyAlpha, kChi2Tests));
}

TEST(AliasTable, DenseGridOfUDrawsEachIndexInProportionToItsWeight) {
    // u on a grid of 2^20 evenly spaced values: each index is drawn for a union of intervals of
    // u whose total length is its probability, so its grid count matches it to within the grid
    // spacing per interval end (at most two intervals per bin, one bin per index).
    const std::vector<float> weights = {0, 1, 3, 0, 0.5f, 1e-4f, 7, 0, 2.5f};
    AliasTable table(weights);
    const int n = int(weights.size()), grid = 1 << 20;
    std::vector<double> count(size_t(n), 0);
    for (int k = 0; k < grid; ++k) count[table.sample(float(k) / float(grid))] += 1;
    double total = 0;
    for (float w : weights) total += w;
    for (int i = 0; i < n; ++i) {
        double expected = weights[size_t(i)] / total;
        EXPECT_NEAR(table.pmf(uint32_t(i)), expected, 1e-7) << "index " << i;
        if (weights[size_t(i)] == 0) {
            EXPECT_EQ(count[size_t(i)], 0) << "index " << i;
        }
        EXPECT_NEAR(count[size_t(i)] / grid, expected, 2.0 * n / grid) << "index " << i;
    }
}

TEST(AliasTable, RandomWeightsPassChiSquare) {
    Rng weightsRng(11, 3);
    std::vector<float> weights(200);
    // Spread over six orders of magnitude, a fifth of them zero.
    for (float& w : weights)
        w = weightsRng.nextFloat() < 0.2f ? 0.0f : std::pow(10.0f, 6 * weightsRng.nextFloat() - 3);
    AliasTable table(weights);
    std::vector<double> expected, observed(weights.size(), 0);
    for (size_t i = 0; i < weights.size(); ++i) expected.push_back(table.pmf(uint32_t(i)));
    Rng rng(12, 4);
    const int n = 1'000'000;
    for (int i = 0; i < n; ++i) observed[table.sample(rng.nextFloat())] += 1;
    for (size_t i = 0; i < weights.size(); ++i)
        if (weights[i] == 0) {
            EXPECT_EQ(observed[i], 0) << "index " << i;
        }
    EXPECT_GE(discreteChi2PValue(observed, expected, n),
              test::sidakLevel(kFamilyAlpha, kChi2Tests));
}

TEST(AliasTable, InvalidWeightsCountAsZero) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    EXPECT_TRUE(AliasTable(std::vector<float>{}).empty());
    EXPECT_TRUE(AliasTable(std::vector<float>{0, -1, nan, inf}).empty());
    AliasTable one(std::vector<float>{nan, -2, 5, inf});
    ASSERT_FALSE(one.empty());
    EXPECT_EQ(one.pmf(2), 1.0f);
    for (float u : {0.0f, 0.1f, 0.25f, 0.5f, 0.74f, 0.75f, 0.99f, 0x1.fffffep-1f})
        EXPECT_EQ(one.sample(u), 2u) << "u " << u;
}

TEST(LightSampling, UniformConeMatchesItsPdf) {
    const float cosMax = 0.8f;
    test::DirectionSampler sampler = [&](Rng& rng) -> std::optional<Vec3f> {
        return sampleUniformCone({rng.nextFloat(), rng.nextFloat()}, cosMax);
    };
    test::DirectionPdf pdf = [&](Vec3f w) -> double {
        return w.z >= cosMax ? uniformConePdf(cosMax) : 0.0;
    };
    Rng rng(9, 9);
    auto result = test::chi2Test(sampler, pdf, rng);
    EXPECT_GE(result.pValue, test::sidakLevel(kFamilyAlpha, kChi2Tests)) << result.describe();
}

TEST(LightSampling, UniformSphereMatchesItsPdf) {
    test::DirectionSampler sampler = [](Rng& rng) -> std::optional<Vec3f> {
        return sampleUniformSphere({rng.nextFloat(), rng.nextFloat()});
    };
    test::DirectionPdf pdf = [](Vec3f) -> double { return uniformSpherePdf(); };
    Rng rng(10, 10);
    auto result = test::chi2Test(sampler, pdf, rng);
    EXPECT_GE(result.pValue, test::sidakLevel(kFamilyAlpha, kChi2Tests)) << result.describe();
}

TEST(LightSampling, TentFilterOffsetsFollowTheTent) {
    const int bins = 40, n = 200000;
    std::vector<double> observed(bins, 0), probability(bins, 0);
    for (int b = 0; b < bins; ++b) {
        // Exact integral of the tent 1 - |x| over the bin [x0, x1].
        double x0 = -1 + 2.0 * b / bins, x1 = -1 + 2.0 * (b + 1) / bins;
        auto cdf = [](double x) {
            return x < 0 ? 0.5 * (1 + x) * (1 + x) : 1 - 0.5 * (1 - x) * (1 - x);
        };
        probability[size_t(b)] = cdf(x1) - cdf(x0);
    }
    Rng rng(11, 11);
    for (int i = 0; i < n; ++i) {
        float x = sampleTent(rng.nextFloat());
        ASSERT_GE(x, -1.0f);
        ASSERT_LE(x, 1.0f);
        observed[size_t(std::min(bins - 1, int((x + 1) / 2 * bins)))] += 1;
    }
    EXPECT_GE(discreteChi2PValue(observed, probability, n),
              test::sidakLevel(kFamilyAlpha, kChi2Tests));
}

}  // namespace
}  // namespace partita
