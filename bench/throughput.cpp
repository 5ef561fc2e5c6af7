#include "throughput.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

#include "gltf/gltf_loader.h"
#include "integrators/pt/pt_integrator.h"
#include "math/frame.h"
#include "render_scene.h"
#include "renderer.h"
#include "rng.h"
#include "sampling.h"
#include "thread_pool.h"

namespace partita::eval {

namespace {

double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

/// Incoherent rays: origins on random scene surfaces (found by first tracing rays from random
/// points in the bounds), directions cosine-distributed in the hemisphere facing where the probe
/// came from. This is the secondary-ray workload a path tracer generates (bounces leave a
/// surface on the side they arrived), without any of its shading; uniform sphere directions
/// would send half the rays straight out of closed rooms, which flatters the kernel.
std::vector<Ray> makeIncoherentRays(const RenderScene& scene, int count) {
    std::vector<Ray> rays;
    rays.reserve(size_t(count));
    Rng rng(12345, 0);
    Bounds3f b = scene.bounds();
    Vec3f extent = b.diagonal();
    int attempts = 0;
    while (int(rays.size()) < count && attempts < count * 20) {
        ++attempts;
        Vec3f o = b.lo + extent * Vec3f(rng.nextFloat(), rng.nextFloat(), rng.nextFloat());
        Ray probe{o, sampleUniformSphere({rng.nextFloat(), rng.nextFloat()}), kInf};
        auto hit = scene.intersect(probe);
        if (!hit) continue;
        Frame frame = Frame::fromNormal(faceForward(hit->ng, -probe.d));
        Vec3f d = frame.toWorld(sampleCosineHemisphere({rng.nextFloat(), rng.nextFloat()}));
        rays.push_back(spawnRay(hit->p, hit->ng, d));
    }
    return rays;
}

double measureEmbreeRaysPerSecond(const RenderScene& scene, const std::vector<Ray>& rays, int repeats) {
    std::vector<float> t(rays.size());
    double best = 0;
    for (int r = 0; r < repeats; ++r) {
        auto start = std::chrono::steady_clock::now();
        scene.intersectRaw(rays.data(), rays.size(), t.data());
        best = std::max(best, double(rays.size()) / secondsSince(start));
    }
    return best;
}

struct PtMeasurement {
    double raysPerSecond = 0, samplesPerSecond = 0;
};

PtMeasurement measurePathTracer(const RenderScene& scene, const ThroughputOptions& o, int threads) {
    RenderSettings s;
    s.width = o.width;
    s.height = o.height;
    s.budget = o.spp;
    s.maxDepth = o.maxDepth;
    s.cameraName = o.camera;
    s.previewIntervalSeconds = 0;
    ThreadPool pool(threads);
    std::atomic<bool> cancel{false};
    RenderObserver quiet;
    PtMeasurement best;
    for (int r = 0; r < o.repeats; ++r) {
        RenderResult res = runRender(scene, "pt", s, pool, cancel, quiet);
        // The sampling passes only: the Embree side is timed around its queries only, so setup
        // and the final Film::resolve (single-threaded) stay out of both rates.
        double seconds = res.stats.values["render_seconds"];
        best.raysPerSecond = std::max(best.raysPerSecond, res.stats.values["rays"] / seconds);
        best.samplesPerSecond = std::max(best.samplesPerSecond, double(s.width) * s.height * o.spp / seconds);
    }
    return best;
}

}  // namespace

nlohmann::json runThroughput(const ThroughputOptions& o) {
    RenderScene scene(loadGltfFile(o.scene));
    std::vector<Ray> rays = makeIncoherentRays(scene, o.rays);
    if (rays.empty()) throw std::runtime_error("could not generate benchmark rays: the scene has no surfaces");

    // Interleave the measurements so slow phases of a shared machine hit both alike.
    double embree = measureEmbreeRaysPerSecond(scene, rays, o.repeats);
    PtMeasurement one = measurePathTracer(scene, o, 1);
    embree = std::max(embree, measureEmbreeRaysPerSecond(scene, rays, o.repeats));
    int hw = int(std::max(1u, std::thread::hardware_concurrency()));
    std::vector<int> counts = {1};
    for (int n = 2; n <= hw; n *= 2) counts.push_back(n);
    if (counts.back() != hw) counts.push_back(hw);

    nlohmann::json out;
    out["scene"] = o.scene;
    out["width"] = o.width;
    out["height"] = o.height;
    out["spp"] = o.spp;
    out["embree_rays_per_s"] = embree;
    out["pt_rays_per_s"] = one.raysPerSecond;
    out["ratio"] = one.raysPerSecond / embree;
    std::printf("scene %s (%dx%d, %d spp per run, best of %d)\n", o.scene.c_str(), o.width, o.height, o.spp,
                o.repeats);
    std::printf("  %-34s %12.3f M rays/s (1 thread)\n", "embree rtcIntersect1 incoherent", embree / 1e6);
    std::printf("  %-34s %12.3f M rays/s (1 thread)\n", "path tracer (all rays)", one.raysPerSecond / 1e6);
    std::printf("  %-34s %12.3f  (target >= 0.6)\n", "ratio pt / embree", one.raysPerSecond / embree);
    nlohmann::json threads = nlohmann::json::array();
    double base = one.samplesPerSecond;
    for (int n : counts) {
        PtMeasurement m = n == 1 ? one : measurePathTracer(scene, o, n);
        threads.push_back({{"n", n}, {"samples_per_s", m.samplesPerSecond}, {"speedup", m.samplesPerSecond / base}});
        std::printf("  threads %-3d %12.3f M samples/s   speedup %.2fx\n", n, m.samplesPerSecond / 1e6,
                    m.samplesPerSecond / base);
    }
    out["threads"] = threads;
    return out;
}

}  // namespace partita::eval
