// The reference path tracer against answers known in closed form, and its determinism.
#include <gtest/gtest.h>

#include <cmath>

#include "camera.h"
#include "film.h"
#include "integrators/pt/film_sink.h"
#include "integrators/pt/path_sampler.h"
#include "integrators/pt/pt_integrator.h"
#include "render_helpers.h"
#include "sampling.h"
#include "scene_builders.h"

namespace partita {
namespace {

using test::meanAndError;
using test::renderWith;

/// A closed box whose walls all emit Le and reflect diffusely with albedo rho. Every path sees
/// radiance Le (1 + rho + rho^2 + ...) = Le / (1 - rho); the paths with k diffuse vertices
/// (type L D^k E) carry exactly Le rho^k.
SceneData furnaceScene(float rho, float le) {
    SceneData s;
    s.materials = {test::lambertMaterial(Rgb(rho), Rgb(le), true)};
    s.meshes.push_back(test::box({-1, -1, -1}, {1, 1, 1}, 0, true));
    s.cameras.push_back(test::lookAtCamera({0, 0, 0.5f}, {0, 0, -1}, 1.2f));
    return s;
}

RenderSettings smallSettings(int spp, uint64_t seed, int maxDepth = 64) {
    RenderSettings s;
    s.width = 24;
    s.height = 16;
    s.budget = spp;
    s.seed = seed;
    s.maxDepth = maxDepth;
    s.previewIntervalSeconds = 0;
    return s;
}

TEST(PathTracer, WhiteFurnaceMatchesClosedForm) {
    const float rho = 0.5f, le = 1.0f;
    RenderScene scene(furnaceScene(rho, le));
    std::vector<double> means;
    std::vector<std::vector<double>> perType(4);
    for (uint64_t seed = 1; seed <= 8; ++seed) {
        RenderResult r = renderWith(scene, "pt", smallSettings(4, seed));
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

TEST(PathTracer, MaxDepthTruncatesTheNeumannSeries) {
    const float rho = 0.5f, le = 1.0f;
    RenderScene scene(furnaceScene(rho, le));
    std::vector<double> means;
    for (uint64_t seed = 11; seed <= 18; ++seed)
        means.push_back(
            luminance(renderWith(scene, "pt", smallSettings(4, seed, 2)).image.combined.mean()));
    auto m = meanAndError(means);
    double expected = le * (1 + rho + rho * rho);  // at most two scattering vertices
    EXPECT_NEAR(m.mean, expected, test::statisticalTolerance(m, expected));
}

/// A Lambertian floor (albedo rho) under a point light of intensity I at height h, seen by an
/// orthographic camera looking straight down: L(x, z) = rho / pi * I * h / d^3. The expected
/// pixel value is L averaged over the pixel's tent filter, computed here by Gauss-Legendre
/// quadrature, an estimator independent of the renderer.
TEST(PathTracer, PointLightOverLambertPlaneMatchesQuadrature) {
    const float rho = 0.8f, intensity = 5.0f, h = 1.0f, halfExtent = 1.0f;
    const int res = 12;
    SceneData s;
    s.materials = {test::lambertMaterial(Rgb(rho))};
    s.meshes.push_back(test::quad({-10, 0, -10}, {0, 0, 20}, {20, 0, 0}, 0));  // normal +y
    PunctualLightDesc light;
    light.type = PunctualLightDesc::Type::Point;
    light.intensity = intensity;
    light.position = {0.3f, h, -0.2f};
    s.lights.push_back(light);
    CameraDesc cam = test::lookAtCamera({0, 5, 0}, {0, 0, 0}, 1.0f);
    cam.type = CameraDesc::Type::Orthographic;
    cam.ymag = halfExtent;
    s.cameras.push_back(cam);
    RenderScene scene(std::move(s));

    auto radiance = [&](double x, double z) {
        double dx = x - 0.3, dz = z + 0.2;
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
                        Ray ray = camera.generateRay({float(px + 0.5 + u), float(py + 0.5 + v)});
                        sum += w * radiance(ray.o.x, ray.o.z);
                    }
        return sum;
    };
    const int seeds = 8;
    std::vector<std::vector<double>> perPixel(size_t(res * res));
    for (int seed = 0; seed < seeds; ++seed) {
        RenderSettings st = smallSettings(8, 100 + seed, 1);
        st.width = st.height = res;
        RenderResult r = renderWith(scene, "pt", st);
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

TEST(PathTracer, TypeLayersSumToCombined) {
    RenderScene scene(test::specularBoxScene());
    RenderSettings st = smallSettings(8, 7, 12);
    st.width = 32;
    st.height = 24;
    st.maxTypeLayers = 1024;  // keep every type: the layers are then complete
    RenderResult r = renderWith(scene, "pt", st);
    ASSERT_GT(r.image.layers.size(), 4u);
    bool sawSpecular = false;
    for (const auto& layer : r.image.layers)
        sawSpecular |= layer.name.find('S') != std::string::npos;
    EXPECT_TRUE(sawSpecular);
    for (int y = 0; y < st.height; ++y)
        for (int x = 0; x < st.width; ++x) {
            Rgb sum(0.0f);
            for (const auto& layer : r.image.layers) sum += layer.image.at(x, y);
            Rgb c = r.image.combined.at(x, y);
            // Float sums in a different order: a relative rounding bound, not a statistical one.
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(sum[k], c[k], 1e-4f * std::max(1.0f, c[k]));
        }
}

TEST(PathTracer, ImageDoesNotDependOnThreadCountOrPassSplit) {
    RenderScene scene(test::specularBoxScene());
    RenderSettings st = smallSettings(6, 3, 8);
    st.width = 40;
    st.height = 30;
    RenderResult one = renderWith(scene, "pt", st, 1);
    RenderResult two = renderWith(scene, "pt", st, 2);
    st.previewIntervalSeconds = 1e-9;  // passes of one sample each
    RenderResult split = renderWith(scene, "pt", st, 2);
    EXPECT_GT(luminance(one.image.combined.mean()), 0.0f);
    EXPECT_EQ(one.image.combined.rgb, two.image.combined.rgb);
    EXPECT_EQ(one.image.combined.rgb, split.image.combined.rgb);
    ASSERT_EQ(one.image.layers.size(), two.image.layers.size());
    for (size_t i = 0; i < one.image.layers.size(); ++i) {
        EXPECT_EQ(one.image.layers[i].name, two.image.layers[i].name);
        EXPECT_EQ(one.image.layers[i].image.rgb, two.image.layers[i].image.rgb);
    }
}

TEST(PathTracer, PathsTracedInPairsAddExactlyWhatSinglePathsAdd) {
    // The integrator traces two pixels' paths in lockstep (samplePathPair); each pixel must get
    // the same contributions, in the same order, as from samplePath: the films are equal bit
    // for bit. Primary rays leave a point inside the box in directions drawn from each pixel's
    // own stream, so that every kind of vertex (diffuse, mirror, glass, light) is reached.
    RenderScene scene(test::specularBoxScene());
    const int width = 16, height = 8, spp = 4;
    PathSamplerSettings settings;
    settings.maxDepth = 12;
    auto primary = [](Rng& rng) {
        Vec2f u{rng.nextFloat(), rng.nextFloat()};
        return Ray{{0.1f, 1.0f, 0.3f}, sampleUniformSphere(u), kInf};
    };
    Film single(width, height), paired(width, height), pretraced(width, height);
    PathCounters singleCounters, pairedCounters, pretracedCounters;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            FilmSink sink(single, x, y);
            for (int s = 0; s < spp; ++s) {
                Rng rng = pixelSampleRng(5, x, y, width, uint64_t(s));
                samplePath(scene, primary(rng), rng, settings, sink, singleCounters);
            }
        }
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; x += 2) {
            FilmSink sinkA(paired, x, y), sinkB(paired, x + 1, y);
            for (int s = 0; s < spp; ++s) {
                Rng rngA = pixelSampleRng(5, x, y, width, uint64_t(s));
                Rng rngB = pixelSampleRng(5, x + 1, y, width, uint64_t(s));
                PathStart a{primary(rngA), rngA, sinkA}, b{primary(rngB), rngB, sinkB};
                samplePathPair(scene, a, b, settings, pairedCounters);
            }
        }
    // Paths whose primary ray was traced before they start (as the integrator traces camera
    // rays in packets) add the same again, the primary ray counted once.
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            FilmSink sink(pretraced, x, y);
            for (int s = 0; s < spp; ++s) {
                Rng rng = pixelSampleRng(5, x, y, width, uint64_t(s));
                Ray ray = primary(rng);
                SurfaceHit hit;
                bool found = scene.intersect(ray, hit);
                samplePath(scene, PathStart{ray, rng, sink, true, found ? &hit : nullptr}, settings,
                           pretracedCounters);
            }
        }
    EXPECT_EQ(singleCounters.rays, pairedCounters.rays);
    EXPECT_EQ(singleCounters.rays, pretracedCounters.rays);
    LayeredImage three = pretraced.resolve(1.0f, 1024);
    LayeredImage one = single.resolve(1.0f, 1024), two = paired.resolve(1.0f, 1024);
    EXPECT_EQ(one.combined.rgb, three.combined.rgb);
    EXPECT_GT(luminance(one.combined.mean()), 0.0f);
    EXPECT_GT(one.layers.size(), 4u);
    EXPECT_EQ(one.combined.rgb, two.combined.rgb);
    ASSERT_EQ(one.layers.size(), two.layers.size());
    for (size_t i = 0; i < one.layers.size(); ++i) {
        EXPECT_EQ(one.layers[i].name, two.layers[i].name);
        EXPECT_EQ(one.layers[i].image.rgb, two.layers[i].image.rgb);
    }
}

TEST(PathTracer, CameraRayPacketsFindTheHitsOfSingleRays) {
    // The integrator traces the camera rays of up to 8 neighbouring pixels as one Embree packet
    // (RenderScene::intersect8). Each lane must find what the single-ray query finds: the same
    // triangle, at the same distance up to the kernels' rounding, and misses where it misses.
    RenderScene scene(test::specularBoxScene());
    Camera camera(scene.data().cameras.at(0), 64, 48);
    int hitsCompared = 0;
    for (int count = 1; count <= 8; ++count)
        for (int y = 0; y < 48; y += 3)
            for (int x0 = 0; x0 + count <= 64; x0 += 5) {
                Ray rays[8];
                SurfaceHit packetHits[8];
                bool found[8];
                for (int i = 0; i < count; ++i)
                    rays[i] = camera.generateRay({float(x0 + i) + 0.5f, float(y) + 0.5f});
                scene.intersect8(rays, count, packetHits, found);
                for (int i = 0; i < count; ++i) {
                    SurfaceHit single;
                    bool singleFound = scene.intersect(rays[i], single);
                    ASSERT_EQ(found[i], singleFound) << "pixel " << x0 + i << ", " << y;
                    if (!singleFound) continue;
                    const SurfaceHit& h = packetHits[i];
                    ASSERT_EQ(h.mesh, single.mesh);
                    ASSERT_EQ(h.triangle, single.triangle);
                    EXPECT_NEAR(h.t, single.t, 1e-5f * single.t);
                    EXPECT_NEAR(h.p.x, single.p.x, 1e-4f);
                    EXPECT_NEAR(h.p.y, single.p.y, 1e-4f);
                    EXPECT_NEAR(h.p.z, single.p.z, 1e-4f);
                    EXPECT_EQ(h.ng, single.ng);
                    ++hitsCompared;
                }
            }
    EXPECT_GT(hitsCompared, 1000);
}

class CancelOnFirstProgress : public RenderObserver {
  public:
    explicit CancelOnFirstProgress(std::atomic<bool>& flag) : flag_(flag) {}
    void onProgress(const RenderProgress&) override { flag_.store(true); }

  private:
    std::atomic<bool>& flag_;
};

TEST(PathTracer, CancelStopsTheRender) {
    RenderScene scene(test::specularBoxScene());
    RenderSettings st = smallSettings(100000, 1, 8);
    ThreadPool pool(2);
    std::atomic<bool> cancel{false};
    CancelOnFirstProgress observer(cancel);
    EXPECT_THROW(runRender(scene, "pt", st, pool, cancel, observer), RenderCancelled);
}

TEST(PathTracer, UnknownAlgorithmIsAnError) {
    RenderScene scene(test::specularBoxScene());
    EXPECT_THROW(renderWith(scene, "nope", smallSettings(1, 1)), std::invalid_argument);
}

}  // namespace
}  // namespace partita
