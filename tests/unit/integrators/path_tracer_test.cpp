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

// The closed-form checks (furnace, maximum depth, point light over a plane) run for every
// registered algorithm: integrators/every_algorithm_test.cpp.

TEST(PathTracer, TypeLayersSumToCombined) {
    RenderScene scene(test::specularBoxScene());
    RenderSettings st = smallSettings(8, 7, 12);
    st.width = 32;
    st.height = 24;
    st.everyTypeLayer = true;  // keep every type: the layers are then complete
    st.maxTypeLayers = 1024;
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
