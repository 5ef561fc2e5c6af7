// Checks with answers known in closed form, run for every registered algorithm (pt, bdpt, and
// each later one automatically): a closed furnace per type, the maximum depth, and a point light
// over a Lambertian plane against quadrature.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "algorithm.h"
#include "camera.h"
#include "environment_map.h"
#include "render_helpers.h"
#include "scene_builders.h"

namespace partita {
namespace {

using test::meanAndError;
using test::renderWith;

std::vector<std::string> registeredAlgorithms() {
    registerBuiltinAlgorithms();
    return AlgorithmRegistry::instance().names();
}

class EveryAlgorithm : public ::testing::TestWithParam<std::string> {
  protected:
    /// Settings for the algorithm under test with its native budget (samples or mutations per
    /// pixel).
    RenderSettings smallSettings(int spp, uint64_t seed, int maxDepth = 64) const {
        RenderSettings s;
        s.budgetKind = AlgorithmRegistry::instance().find(GetParam())->nativeBudget;
        s.width = 24;
        s.height = 16;
        s.budget = spp;
        s.seed = seed;
        s.maxDepth = maxDepth;
        s.previewIntervalSeconds = 0;
        return s;
    }
    /// smallSettings, where an algorithm's layers are partitions (those with "estimators":
    /// partitioned, guided) keeping the direct light (LE, LDE) with its types instead of a
    /// partition of its own (pipeline_settings.h "direct"): every type a layer of its own.
    RenderSettings perTypeSettings(int spp, uint64_t seed, int maxDepth = 64) const {
        RenderSettings s = smallSettings(spp, seed, maxDepth);
        for (const ParameterSpec& p : AlgorithmRegistry::instance().find(GetParam())->parameters)
            if (p.name == "estimators") s.parameters.set("direct", std::string("chains"));
        return s;
    }
};

TEST_P(EveryAlgorithm, WhiteFurnaceMatchesClosedForm) {
    const float rho = 0.5f, le = 1.0f;
    RenderScene scene(test::furnaceScene(rho, le));
    std::vector<double> means;
    std::vector<std::vector<double>> perType(4);
    for (uint64_t seed = 1; seed <= 8; ++seed) {
        RenderResult r = renderWith(scene, GetParam(), perTypeSettings(4, seed));
        means.push_back(luminance(r.image.combined.mean()));
        for (int k = 0; k < 4; ++k) {
            std::string name = "L" + std::string(size_t(k), 'D') + "E";
            const Image* layer = r.image.layer(name);
            ASSERT_NE(layer, nullptr) << name;
            perType[size_t(k)].push_back(luminance(layer->mean()));
        }
    }
    auto total = meanAndError(means);
    double expected = le / (1 - rho);
    EXPECT_GT(total.standardError, 0);
    EXPECT_NEAR(total.mean, expected, test::statisticalTolerance(total, expected, 5));
    for (int k = 0; k < 4; ++k) {
        auto m = meanAndError(perType[size_t(k)]);
        double want = le * std::pow(rho, k);
        EXPECT_NEAR(m.mean, want, test::statisticalTolerance(m, want, 5))
            << "type with " << k << " D vertices";
    }
}

TEST_P(EveryAlgorithm, MaxDepthTruncatesTheNeumannSeries) {
    const float rho = 0.5f, le = 1.0f;
    RenderScene scene(test::furnaceScene(rho, le));
    std::vector<double> means;
    for (uint64_t seed = 11; seed <= 18; ++seed)
        means.push_back(luminance(
            renderWith(scene, GetParam(), smallSettings(4, seed, 2)).image.combined.mean()));
    auto m = meanAndError(means);
    double expected = le * (1 + rho + rho * rho);  // at most two scattering vertices
    EXPECT_NEAR(m.mean, expected, test::statisticalTolerance(m, expected));
}

/// A Lambertian floor (albedo rho) under a point light of intensity I at height h, seen from
/// above: L(x, z) = rho / pi * I * h / d^3, whatever the view direction. The expected pixel value
/// is L at the floor point each camera ray reaches, averaged over the pixel's tent filter by
/// Gauss-Legendre quadrature: an estimator independent of the renderer.
void expectPointLightOverLambertPlane(const std::string& algorithm, CameraDesc cam,
                                      const std::function<RenderSettings(uint64_t)>& settings) {
    const float rho = 0.8f, intensity = 5.0f, h = 1.0f;
    const int res = 12;
    SceneData s;
    s.materials = {test::lambertMaterial(Rgb(rho))};
    s.meshes.push_back(test::quad({-10, 0, -10}, {0, 0, 20}, {20, 0, 0}, 0));  // normal +y
    PunctualLightDesc light;
    light.type = PunctualLightDesc::Type::Point;
    light.intensity = intensity;
    light.position = {0.3f, h, -0.2f};
    s.lights.push_back(light);
    s.cameras.push_back(cam);
    RenderScene scene(std::move(s));

    auto radiance = [&](const Ray& ray) {
        double t = -double(ray.o.y) / ray.d.y;  // the floor y = 0
        double dx = ray.o.x + t * ray.d.x - 0.3, dz = ray.o.z + t * ray.d.z + 0.2;
        double d2 = dx * dx + dz * dz + h * h;
        return rho / M_PI * intensity * h / (d2 * std::sqrt(d2));
    };
    Camera camera(cam, res, res);
    // 8-point Gauss-Legendre on each half [-1,0], [0,1] of the tent.
    const double gx[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                          -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                          0.7966664774136267,  0.9602898564975363};
    const double gw[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                          0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                          0.2223810344533745, 0.1012285362903763};
    auto expectedPixel = [&](int px, int py) {
        double sum = 0;
        for (int hx = 0; hx < 2; ++hx)
            for (int i = 0; i < 8; ++i)
                for (int hy = 0; hy < 2; ++hy)
                    for (int j = 0; j < 8; ++j) {
                        double u = (gx[i] + 1) / 2 - hx, v = (gx[j] + 1) / 2 - hy;  // in [-1, 1]
                        double w = gw[i] / 2 * gw[j] / 2 * (1 - std::abs(u)) * (1 - std::abs(v));
                        sum += w * radiance(camera.generateRay(
                                       {float(px + 0.5 + u), float(py + 0.5 + v)}));
                    }
        return sum;
    };
    const int seeds = 8;
    std::vector<std::vector<double>> perPixel(size_t(res * res));
    for (int seed = 0; seed < seeds; ++seed) {
        RenderSettings st = settings(100 + uint64_t(seed));
        st.width = st.height = res;
        RenderResult r = renderWith(scene, algorithm, st);
        for (int y = 0; y < res; ++y)
            for (int x = 0; x < res; ++x)
                perPixel[size_t(y * res + x)].push_back(r.image.combined.at(x, y).y);
    }
    for (int y = 0; y < res; ++y)
        for (int x = 0; x < res; ++x) {
            auto m = meanAndError(perPixel[size_t(y * res + x)]);
            double want = expectedPixel(x, y);
            EXPECT_GT(m.standardError, 0);
            EXPECT_NEAR(m.mean, want, test::statisticalTolerance(m, want, res * res))
                << "pixel " << x << "," << y;
        }
}

TEST_P(EveryAlgorithm, PointLightOverLambertPlaneMatchesQuadratureOrthographic) {
    if (!AlgorithmRegistry::instance().find(GetParam())->orthographicCamera)
        GTEST_SKIP() << GetParam() << " needs a perspective camera";
    CameraDesc cam = test::lookAtCamera({0, 5, 0}, {0, 0, 0}, 1.0f);
    cam.type = CameraDesc::Type::Orthographic;
    cam.ymag = 1.0f;
    expectPointLightOverLambertPlane(GetParam(), cam,
                                     [&](uint64_t seed) { return smallSettings(8, seed, 1); });
}

TEST_P(EveryAlgorithm, PointLightOverLambertPlaneMatchesQuadraturePerspective) {
    // Below the light, so that the light itself is out of view (pt cannot see a point light).
    CameraDesc cam = test::lookAtCamera({0, 0.6f, 0.01f}, {0, 0, 0}, 1.2f);
    expectPointLightOverLambertPlane(GetParam(), cam,
                                     [&](uint64_t seed) { return smallSettings(8, seed, 1); });
}

/// A cube of albedo rho (flat faces: shading and geometric normals agree) under a uniform
/// environment Le: convex, so every face point sees the whole sky once, L = rho Le, and nothing
/// reflects twice. A pixel's background part is type LE and its cube part LDE, so whatever the
/// cube covers of it, LE + LDE / rho = Le exactly, pixel by pixel, and no other type exists.
TEST_P(EveryAlgorithm, CubeUnderAUniformEnvironmentMatchesClosedForm) {
    const float rho = 0.5f, le = 1.5f;
    SceneData s;
    s.materials = {test::lambertMaterial(Rgb(rho))};
    s.meshes.push_back(test::box({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}, 0, false));
    s.environment = std::make_shared<EnvironmentMap>(EnvironmentMap::uniform(Rgb(le)));
    s.cameras.push_back(test::lookAtCamera({1.2f, 0.9f, 1.6f}, {0, 0, 0}, 1.0f));
    RenderScene scene(std::move(s));
    const int seeds = 6;
    RenderSettings st = perTypeSettings(8, 1, 8);
    std::vector<std::vector<double>> perPixel(size_t(st.width * st.height));
    double otherTypes = 0, cube = 0;
    for (int seed = 0; seed < seeds; ++seed) {
        st.seed = 40 + uint64_t(seed);
        RenderResult r = renderWith(scene, GetParam(), st);
        const Image* background = r.image.layer("LE");
        const Image* lit = r.image.layer("LDE");
        ASSERT_TRUE(background && lit);
        for (const auto& layer : r.image.layers)
            if (layer.name != "LE" && layer.name != "LDE")
                otherTypes += luminance(layer.image.mean());
        cube += luminance(lit->mean());
        for (int y = 0; y < st.height; ++y)
            for (int x = 0; x < st.width; ++x)
                perPixel[size_t(y * st.width + x)].push_back(background->at(x, y).y +
                                                             lit->at(x, y).y / rho);
    }
    EXPECT_EQ(otherTypes, 0.0);
    EXPECT_GT(cube, 0.0);
    int comparisons = st.width * st.height;
    for (int i = 0; i < comparisons; ++i) {
        auto m = meanAndError(perPixel[size_t(i)]);
        EXPECT_NEAR(m.mean, le, test::statisticalTolerance(m, le, comparisons)) << "pixel " << i;
    }
}

TEST_P(EveryAlgorithm, ImageDoesNotDependOnThreadCountOrPassSplit) {
    RenderScene scene(test::specularBoxScene());
    RenderSettings st = smallSettings(4, 3, 8);
    st.width = 40;
    st.height = 30;
    RenderResult one = renderWith(scene, GetParam(), st, 1);
    RenderResult two = renderWith(scene, GetParam(), st, 2);
    st.previewIntervalSeconds = 1e-9;  // passes of one sample each
    RenderResult split = renderWith(scene, GetParam(), st, 2);
    EXPECT_GT(luminance(one.image.combined.mean()), 0.0f);
    EXPECT_EQ(one.image.combined.rgb, two.image.combined.rgb);
    EXPECT_EQ(one.image.combined.rgb, split.image.combined.rgb);
    ASSERT_EQ(one.image.layers.size(), two.image.layers.size());
    for (size_t i = 0; i < one.image.layers.size(); ++i) {
        EXPECT_EQ(one.image.layers[i].name, two.image.layers[i].name);
        EXPECT_EQ(one.image.layers[i].image.rgb, two.image.layers[i].image.rgb);
    }
}

INSTANTIATE_TEST_SUITE_P(Registered, EveryAlgorithm, ::testing::ValuesIn(registeredAlgorithms()),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace partita
