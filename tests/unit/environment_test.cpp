// The environment map: its importance sampling against its own pdf (chi-square), the pdf
// against the radiance it should follow, and its lookups; and the environment as a light of the
// path tracer and BDPT (the furnace that checks both is in integrators/every_algorithm_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "chi2.h"
#include "environment_map.h"
#include "image_io.h"
#include "render_helpers.h"
#include "render_scene.h"
#include "renderer.h"
#include "scene_builders.h"
#include "scene_environment.h"

namespace partita {
namespace {

constexpr double kFamilyAlpha = 1e-3;
constexpr int kChi2Tests = 2;

/// A map with a bright spot, a gradient and a dark band, so that sampling has structure.
Image structuredMap(int w, int h) {
    Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float v = float(y) / float(h), u = float(x) / float(w);
            Rgb c(0.2f + u, 0.5f * v, 0.3f);
            // A near-black band (exactly black edges cannot be resolved by the cubature of the
            // chi-square cells; a black map is tested on its own).
            if (y > h / 2 && y < h / 2 + 3) c = Rgb(0.002f);
            if (std::abs(u - 0.7f) < 0.05f && std::abs(v - 0.3f) < 0.06f) c = Rgb(40.0f);
            img.set(x, y, c);
        }
    return img;
}

TEST(EnvironmentMap, SamplingMatchesItsPdf) {
    for (float rotation : {0.0f, 37.0f}) {
        EnvironmentMap env(structuredMap(48, 24), rotation);
        test::DirectionSampler sampler = [&](Rng& rng) -> std::optional<Vec3f> {
            Vec3f d;
            float pdf;
            if (!env.sample({rng.nextFloat(), rng.nextFloat()}, d, pdf)) return std::nullopt;
            return d;
        };
        test::DirectionPdf pdf = [&](Vec3f d) -> double { return env.pdf(d); };
        Rng rng(5, uint64_t(rotation));
        auto result = test::chi2Test(sampler, pdf, rng);
        EXPECT_EQ(result.supportViolations, 0) << result.describe();
        EXPECT_NEAR(result.pdfIntegral, 1.0, 1e-2) << result.describe();
        EXPECT_GE(result.pValue, test::sidakLevel(kFamilyAlpha, kChi2Tests)) << result.describe();
    }
}

TEST(EnvironmentMap, LooksUpTheDocumentedDirections) {
    Image img(4, 2);
    img.set(2, 0, Rgb(1, 0, 0));  // upper half, u in [0.5, 0.75): towards -Z then +X
    img.set(1, 1, Rgb(0, 1, 0));  // lower half, u in [0.25, 0.5): towards -X then -Z
    EnvironmentMap env(img);
    EXPECT_EQ(env.radiance(normalize(Vec3f(0.3f, 0.5f, -1))), Rgb(1, 0, 0));
    EXPECT_EQ(env.radiance(normalize(Vec3f(-0.3f, -0.5f, -1))), Rgb(0, 1, 0));
    // Rotated by 90 degrees about +Y, -Z's texels move to +X... seen from above, counter-clockwise.
    EnvironmentMap turned(img, 90);
    EXPECT_EQ(turned.radiance(normalize(Vec3f(-1, 0.5f, -0.3f))), Rgb(1, 0, 0));
    EXPECT_TRUE(EnvironmentMap(Image(2, 2)).isBlack());
}

TEST(EnvironmentMap, IsALightOfTheScene) {
    SceneData s;
    s.materials = {test::lambertMaterial(Rgb(0.5f))};
    s.meshes.push_back(test::box({-1, -1, -1}, {1, 1, 1}, 0, false));
    s.environment = std::make_shared<EnvironmentMap>(EnvironmentMap::uniform(Rgb(2.0f)));
    RenderScene scene(std::move(s));
    ASSERT_TRUE(scene.hasEnvironment());
    EXPECT_EQ(scene.lights().size(), 1u);
    EXPECT_EQ(scene.environmentRadiance({0, 1, 0}), Rgb(2.0f));
    auto ls = scene.sampleLight(scene.environmentLightIndex(), {0, 2, 0}, {0.3f, 0.6f});
    ASSERT_TRUE(ls);
    EXPECT_FALSE(ls->isDelta);
    EXPECT_NEAR(ls->pdf, scene.environmentPdf(ls->wi), 1e-5f * ls->pdf);
}

TEST(SceneEnvironment, AttachesAFileOrAColourAndRefusesBadFiles) {
    auto dir = std::filesystem::temp_directory_path() / "partita-env-test";
    std::filesystem::create_directories(dir);
    LayeredImage sky;
    sky.combined = structuredMap(16, 8);
    writeExr(dir / "sky.exr", sky, {});
    SceneData data;
    EnvironmentSettings env;
    env.file = (dir / "sky.exr").string();
    env.rotationDegrees = 15;
    attachEnvironment(data, env);
    ASSERT_TRUE(data.environment);
    EXPECT_EQ(data.environment->radiance({0, 1, 0}),
              EnvironmentMap(sky.combined, 15).radiance({0, 1, 0}));
    EnvironmentSettings colour;
    colour.hasColor = true;
    colour.color = {0.5f, 0.25f, 1};
    attachEnvironment(data, colour);
    EXPECT_EQ(data.environment->radiance({1, 0, 0}), Rgb(0.5f, 0.25f, 1));
    EnvironmentSettings missing;
    missing.file = (dir / "nope.exr").string();
    EXPECT_THROW(attachEnvironment(data, missing), std::invalid_argument);
    std::ofstream(dir / "garbage.exr") << "not an image";
    missing.file = (dir / "garbage.exr").string();
    EXPECT_THROW(attachEnvironment(data, missing), std::invalid_argument);
    std::filesystem::remove_all(dir);
}

TEST(SceneEnvironment, ASceneWithoutLightsWarnsAndSaysSoInTheResult) {
    SceneData s;
    s.materials = {test::lambertMaterial(Rgb(0.5f))};
    s.meshes.push_back(test::box({-1, -1, -1}, {1, 1, 1}, 0, false));
    s.cameras.push_back(test::lookAtCamera({0, 0, 4}, {0, 0, 0}, 1.0f));
    RenderScene dark(s);
    EXPECT_NE(darkSceneWarning(dark), "");
    RenderSettings st;
    st.width = 8;
    st.height = 6;
    st.budget = 1;
    st.previewIntervalSeconds = 0;
    RenderResult r = test::renderWith(dark, "pt", st);
    EXPECT_EQ(r.stats.labels["warning"], darkSceneWarning(dark));
    EXPECT_NE(describeRender("pt", st, r.stats).count("partita:stat:warning"), 0u);
    s.environment = std::make_shared<EnvironmentMap>(EnvironmentMap::uniform(Rgb(1.0f)));
    RenderScene lit(std::move(s));
    EXPECT_EQ(darkSceneWarning(lit), "");
    EXPECT_EQ(test::renderWith(lit, "pt", st).stats.labels.count("warning"), 0u);
}

TEST(SceneEnvironment, SettingsAreValidated) {
    RenderSettings st;
    st.environment.file = "a.exr";
    st.environment.hasColor = true;
    EXPECT_NE(validateSettings(st), "");
    st.environment.file.clear();
    st.environment.color = {1, -1, 0};
    EXPECT_NE(validateSettings(st), "");
    st.environment.color = {1, 1, 1};
    st.environment.rotationDegrees = NAN;
    EXPECT_NE(validateSettings(st), "");
    st.environment.rotationDegrees = 90;
    EXPECT_EQ(validateSettings(st), "");
}

}  // namespace
}  // namespace partita
