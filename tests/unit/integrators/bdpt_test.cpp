// Bidirectional path tracing against the path tracer (per type layer and combined), each
// strategy alone against the closed-form furnace, a point-light caustic that only BDPT can
// render, and the determinism and cancellation every algorithm owes the service.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <thread>

#include "camera.h"
#include "environment_map.h"
#include "gltf/gltf_loader.h"
#include "integrators/bdpt/bdpt_integrator.h"
#include "render_helpers.h"
#include "renderer.h"
#include "scene_builders.h"

namespace partita {
namespace {

using test::meanAndError;
using test::renderWith;

RenderSettings tinySettings(int spp, uint64_t seed, int maxDepth = 16) {
    RenderSettings s;
    s.width = 16;
    s.height = 12;
    s.budget = spp;
    s.seed = seed;
    s.maxDepth = maxDepth;
    s.everyTypeLayer = true;  // every type its own layer: no "other"
    s.maxTypeLayers = 1024;
    s.previewIntervalSeconds = 0;
    return s;
}

/// Renders with a BdptAlgorithm of the given settings (for strategy filters).
RenderResult renderBdpt(const RenderScene& scene, const RenderSettings& settings,
                        const BdptSettings& bdpt, int threads = 2) {
    ThreadPool pool(threads);
    std::atomic<bool> cancel{false};
    RenderObserver observer;
    Camera camera(resolveCamera(scene.data(), settings.cameraName), settings.width,
                  settings.height);
    RenderContext ctx{scene, camera, settings, pool, cancel, observer};
    return BdptAlgorithm(bdpt).render(ctx);
}

/// Mean luminance of each layer ("combined" too) over each quadrant of the image, keyed
/// "NAME/q"; a layer missing from a render counts as zero there.
using RegionSamples = std::map<std::string, std::vector<double>>;

void addRegions(const LayeredImage& img, int seedIndex, RegionSamples& out) {
    auto add = [&](const std::string& name, const Image& im) {
        for (int q = 0; q < 4; ++q) {
            int qx = q % 2, qy = q / 2;
            int x0 = qx * im.width / 2, x1 = (qx + 1) * im.width / 2;
            int y0 = qy * im.height / 2, y1 = (qy + 1) * im.height / 2;
            double sum = 0;
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) sum += luminance(im.at(x, y));
            auto& v = out[name + "/" + std::to_string(q)];
            v.resize(size_t(seedIndex), 0.0);  // zeros for seeds without this layer
            v.push_back(sum / double((x1 - x0) * (y1 - y0)));
        }
    };
    add("combined", img.combined);
    for (const auto& layer : img.layers) {
        ASSERT_NE(layer.name, "other") << "a type was merged away";
        add(layer.name, layer.image);
    }
}

void padTo(RegionSamples& r, int seeds) {
    for (auto& [key, v] : r) v.resize(size_t(seeds), 0.0);
}

/// Compares two sets of region samples wherever a region holds at least `share` of the
/// combined image's mean in either: |mean a - mean b| within the two-sample tolerance of all
/// the comparisons made. Returns the number of regions compared.
int expectRegionsAgree(const RegionSamples& a, const RegionSamples& b, double share,
                       const std::function<bool(const std::string&)>& include) {
    double total = 0;
    for (int q = 0; q < 4; ++q)
        total += meanAndError(a.at("combined/" + std::to_string(q))).mean / 4;
    std::vector<std::string> keys;
    auto consider = [&](const RegionSamples& r) {
        for (const auto& [key, v] : r) {
            if (!include(key.substr(0, key.find('/')))) continue;
            if (meanAndError(v).mean >= share * total &&
                std::find(keys.begin(), keys.end(), key) == keys.end())
                keys.push_back(key);
        }
    };
    consider(a);
    consider(b);
    std::vector<double> zeros(a.begin()->second.size(), 0.0);
    for (const std::string& key : keys) {
        auto ma = meanAndError(a.count(key) ? a.at(key) : zeros);
        auto mb = meanAndError(b.count(key) ? b.at(key) : zeros);
        EXPECT_NEAR(ma.mean, mb.mean, test::twoSampleTolerance(ma, mb, int(keys.size()))) << key;
    }
    return int(keys.size());
}

SceneData loadShipped(const std::string& name) {
    return loadGltfFile(std::string(PARTITA_SCENES_DIR) + "/" + name + "/" + name + ".gltf");
}

/// BDPT and pt per type layer and quadrant, over independent seeds.
void expectBdptMatchesPt(const RenderScene& scene, int seeds, int ptSpp, int bdptSpp,
                         int maxDepth) {
    RegionSamples pt, bdpt;
    for (int i = 0; i < seeds; ++i) {
        addRegions(renderWith(scene, "pt", tinySettings(ptSpp, 1000 + i, maxDepth)).image, i, pt);
        addRegions(renderWith(scene, "bdpt", tinySettings(bdptSpp, 2000 + i, maxDepth)).image, i,
                   bdpt);
    }
    padTo(pt, seeds);
    padTo(bdpt, seeds);
    int compared = expectRegionsAgree(pt, bdpt, 0.01, [](const std::string&) { return true; });
    EXPECT_GE(compared, 4 * 3) << "combined and at least two types";
    std::printf("compared %d type-quadrant regions\n", compared);
}

TEST(Bdpt, AgreesWithPathTracerPerTypeOnCornell) {
    RenderScene scene(loadShipped("cornell"));
    expectBdptMatchesPt(scene, 8, 64, 16, 8);
}

TEST(Bdpt, AgreesWithPathTracerPerTypeOnCornellGlass) {
    RenderScene scene(loadShipped("cornell-glass"));
    expectBdptMatchesPt(scene, 8, 256, 32, 8);
}

TEST(Bdpt, EachStrategyAloneGivesThePerLengthAnswerInTheFurnace) {
    const float rho = 0.5f, le = 1.0f;
    RenderScene scene(test::furnaceScene(rho, le));
    const int seeds = 6, maxK = 2;
    int comparisons = 0;
    for (int k = 0; k <= maxK; ++k) comparisons += k + 2;
    for (int k = 0; k <= maxK; ++k) {
        int n = k + 2;  // vertices of a path with k scattering vertices
        std::string type = "L" + std::string(size_t(k), 'D') + "E";
        for (int t = 1; t <= n; ++t) {
            BdptSettings only;
            only.onlyS = n - t;
            only.onlyT = t;
            only.weighted = false;
            std::vector<double> means;
            for (int i = 0; i < seeds; ++i) {
                RenderResult r = renderBdpt(scene, tinySettings(4, 300 + i, 64), only);
                const Image* layer = r.image.layer(type);
                ASSERT_NE(layer, nullptr) << type << " s=" << n - t << " t=" << t;
                means.push_back(luminance(layer->mean()));
            }
            auto m = meanAndError(means);
            double want = le * std::pow(rho, k);
            EXPECT_GT(m.standardError, 0);
            EXPECT_NEAR(m.mean, want, test::statisticalTolerance(m, want, comparisons))
                << type << " with s=" << n - t << ", t=" << t << " alone";
        }
    }
}

/// A point light above a glass ball over a diffuse floor: the ball focuses the light into a
/// caustic (type LSSDE) that a path tracer cannot sample (a delta light behind a specular
/// chain) and light tracing can.
SceneData causticScene() {
    SceneData s;
    s.materials = {test::lambertMaterial(Rgb(0.8f)), test::glassMaterial(1.5f)};
    s.meshes.push_back(test::quad({-2, 0, -2}, {0, 0, 4}, {4, 0, 0}, 0));  // normal +y
    s.meshes.push_back(test::sphere({0, 0.5f, 0}, 0.3f, 1, 24, 48));
    PunctualLightDesc light;
    light.type = PunctualLightDesc::Type::Point;
    light.intensity = 10;
    light.position = {0, 1.6f, 0};
    s.lights.push_back(light);
    s.cameras.push_back(test::lookAtCamera({0, 1.2f, 2.2f}, {0, 0.2f, 0}, 0.9f));
    return s;
}

TEST(Bdpt, RendersThePointLightCausticThatPtCannotAndLightTracingAgrees) {
    RenderScene scene(causticScene());
    const int seeds = 6;
    RegionSamples bdpt, lightTracing;
    double ptCaustic = 0;
    BdptSettings tracingOnly;
    tracingOnly.onlyT = 1;
    tracingOnly.weighted = false;
    for (int i = 0; i < seeds; ++i) {
        RenderSettings st = tinySettings(16, 500 + i, 6);
        addRegions(renderWith(scene, "bdpt", st).image, i, bdpt);
        addRegions(renderBdpt(scene, st, tracingOnly).image, i, lightTracing);
        if (const Image* l = renderWith(scene, "pt", st).image.layer("LSSDE"))
            ptCaustic += luminance(l->mean());
    }
    padTo(bdpt, seeds);
    padTo(lightTracing, seeds);
    EXPECT_EQ(ptCaustic, 0.0) << "the path tracer cannot sample a point light's caustic";
    double caustic = 0;
    for (int q = 0; q < 4; ++q) caustic += meanAndError(bdpt["LSSDE/" + std::to_string(q)]).mean;
    EXPECT_GT(caustic, 0.0);
    // Light tracing alone sees every type whose first vertex from the camera is diffuse.
    int compared = expectRegionsAgree(bdpt, lightTracing, 0.002, [](const std::string& name) {
        return name != "combined" && name.size() >= 3 && name[name.size() - 2] == 'D';
    });
    EXPECT_GE(compared, 2);
}

/// The specular box with its glass sphere tinted by absorption (KHR_materials_volume): light
/// crossing the sphere is attenuated along its path inside, in both estimators.
TEST(Bdpt, AgreesWithPathTracerThroughAbsorbingGlass) {
    SceneData s = test::specularBoxScene();
    Material& glass = s.materials[3];
    glass.hasVolume = true;
    glass.attenuationColor = Rgb(0.2f, 0.5f, 0.9f);
    glass.attenuationDistance = 0.3f;
    RenderScene scene(std::move(s));
    ASSERT_TRUE(scene.hasAbsorption());
    expectBdptMatchesPt(scene, 8, 128, 16, 8);
}

/// The caustic scene lit by an environment map with a small bright "sun" instead of the point
/// light: both estimators can sample everything, so they must agree per type.
TEST(Bdpt, AgreesWithPathTracerUnderAnEnvironmentMap) {
    SceneData s = causticScene();
    s.lights.clear();
    Image sky(32, 16);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x)
            sky.set(x, y, (y == 2 && x == 15) ? Rgb(400.0f) : Rgb(0.3f, 0.4f, 0.6f + 0.02f * y));
    s.environment = std::make_shared<EnvironmentMap>(std::move(sky), 20.0f);
    RenderScene scene(std::move(s));
    expectBdptMatchesPt(scene, 8, 128, 16, 6);
}

/// A point light in front of the camera, nothing else that reflects: light tracing (s = 1,
/// t = 1) puts the same splat into the image from every light path, so its total has no
/// variance: N_p We(w) cos(theta) I / d^2 over the pixels (the tent weights sum to one). Summed
/// one by one in float, millions of such splats drift by percents; the splat buffer keeps it
/// exact to float rounding, at any spp.
TEST(Bdpt, ADirectlyVisiblePointLightSumsExactlyAtAnySampleCount) {
    SceneData s;
    s.materials = {test::lambertMaterial(Rgb(0.0f))};
    s.meshes.push_back(test::quad({-50, -50, -30}, {100, 0, 0}, {0, 100, 0}, 0));
    PunctualLightDesc light;
    light.type = PunctualLightDesc::Type::Point;
    light.intensity = 3;
    light.position = {0.3f, -0.2f, -2.0f};
    s.lights.push_back(light);
    s.cameras.push_back(test::lookAtCamera({0, 0, 0}, {0, 0, -1}, 0.8f));
    RenderScene scene(s);
    RenderSettings st = tinySettings(1, 1, 4);
    Camera camera(s.cameras[0], st.width, st.height);
    Vec3f d = light.position - camera.position();
    float dist2 = lengthSquared(d), cosTheta = dot(normalize(d), camera.forward());
    double want = double(st.width * st.height) * light.intensity /
                  (camera.imagePlaneArea() * std::pow(cosTheta, 3.0) * dist2);
    for (int spp : {1, 16, 512}) {
        st.budget = spp;
        RenderResult r = renderWith(scene, "bdpt", st);
        const Image* le = r.image.layer("LE");
        ASSERT_NE(le, nullptr);
        double total = 0;
        for (float v : le->rgb) total += v / 3;
        EXPECT_NEAR(total, want, 1e-5 * want) << spp << " spp";
    }
}

TEST(Bdpt, CancelStopsWithinASecond) {
    RenderScene scene(test::specularBoxScene());
    RenderSettings st = tinySettings(1 << 20, 1, 16);
    st.width = 64;
    st.height = 48;
    ThreadPool pool(2);
    std::atomic<bool> cancel{false};
    RenderObserver observer;
    std::thread canceller([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        cancel = true;
    });
    auto start = std::chrono::steady_clock::now();
    EXPECT_THROW(runRender(scene, "bdpt", st, pool, cancel, observer), RenderCancelled);
    double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    canceller.join();
    EXPECT_LT(seconds, 0.3 + 1.0);
}

}  // namespace
}  // namespace partita
