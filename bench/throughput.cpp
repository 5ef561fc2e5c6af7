#include "throughput.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <ctime>
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

double cpuSecondsSince(std::clock_t t) { return double(std::clock() - t) / CLOCKS_PER_SEC; }

/// A single-thread rate measured both ways: by wall clock (what an idle machine shows) and by
/// process CPU time (which leaves out the time other processes held the core, so it is the
/// steadier figure on a shared machine). Best of the repeats for each.
struct Rate {
    double wall = 0, cpu = 0;
    void add(double count, double wallSeconds, double cpuSeconds) {
        wall = std::max(wall, count / wallSeconds);
        if (cpuSeconds > 0) cpu = std::max(cpu, count / cpuSeconds);
    }
    void add(const Rate& o) {
        wall = std::max(wall, o.wall);
        cpu = std::max(cpu, o.cpu);
    }
};

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

Rate measureEmbreeRaysPerSecond(const RenderScene& scene, const std::vector<Ray>& rays,
                                int repeats) {
    std::vector<float> t(rays.size());
    Rate best;
    for (int r = 0; r < repeats; ++r) {
        auto start = std::chrono::steady_clock::now();
        std::clock_t cpuStart = std::clock();
        scene.intersectRaw(rays.data(), rays.size(), t.data());
        best.add(double(rays.size()), secondsSince(start), cpuSecondsSince(cpuStart));
    }
    return best;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    size_t n = v.size();
    return n == 0 ? 0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct PtMeasurement {
    Rate rays;     // for one thread (the CPU time is summed over threads)
    Rate samples;  // per CPU second: what each thread achieves while it runs
};

PtMeasurement measurePathTracer(const RenderScene& scene, const ThroughputOptions& o, int threads,
                                int repeats) {
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
    for (int r = 0; r < repeats; ++r) {
        RenderResult res = runRender(scene, "pt", s, pool, cancel, quiet);
        // The sampling passes only: the Embree side is timed around its queries only, so setup
        // and the final Film::resolve (single-threaded) stay out of both rates.
        double seconds = res.stats.values["render_seconds"];
        double cpuSeconds = res.stats.values["render_cpu_seconds"];
        best.rays.add(res.stats.values["rays"], seconds, cpuSeconds);
        best.samples.add(double(s.width) * s.height * o.spp, seconds, cpuSeconds);
    }
    return best;
}

}  // namespace

nlohmann::json runThroughput(const ThroughputOptions& o) {
    RenderScene scene(loadGltfFile(o.scene));
    std::vector<Ray> rays = makeIncoherentRays(scene, o.rays);
    if (rays.empty())
        throw std::runtime_error("could not generate benchmark rays: the scene has no surfaces");

    // Side by side: each round times the bare kernel and then one path-tracer render, and its
    // ratio compares the two under the same machine conditions. On a shared machine other load
    // comes and goes (and slows the two differently: the path tracer touches more memory), so
    // the headline ratio is the median of the rounds' ratios, not a ratio of two best-ofs taken
    // at different moments.
    Rate embree;
    PtMeasurement one;
    std::vector<double> roundRatios, roundCpuRatios;
    for (int r = 0; r < o.repeats; ++r) {
        Rate e = measureEmbreeRaysPerSecond(scene, rays, 1);
        PtMeasurement p = measurePathTracer(scene, o, 1, 1);
        roundRatios.push_back(p.rays.wall / e.wall);
        roundCpuRatios.push_back(p.rays.cpu / e.cpu);
        embree.add(e);
        one.rays.add(p.rays);
        one.samples.add(p.samples);
    }
    int hw =
        o.maxThreads > 0 ? o.maxThreads : int(std::max(1u, std::thread::hardware_concurrency()));
    std::vector<int> counts = {1};
    for (int n = 2; n <= hw; n *= 2) counts.push_back(n);
    if (counts.back() != hw) counts.push_back(hw);

    nlohmann::json out;
    out["scene"] = o.scene;
    out["width"] = o.width;
    out["height"] = o.height;
    out["spp"] = o.spp;
    out["march"] = PARTITA_EVAL_MARCH;  // the instruction set of this build: compare like with like
    out["embree_rays_per_s"] = embree.wall;
    out["pt_rays_per_s"] = one.rays.wall;
    double ratio = median(roundRatios), ratioCpu = median(roundCpuRatios);
    out["ratio"] = ratio;
    out["ratio_rounds"] = roundRatios;
    out["ratio_of_best_rates"] = one.rays.wall / embree.wall;
    out["embree_rays_per_cpu_s"] = embree.cpu;
    out["pt_rays_per_cpu_s"] = one.rays.cpu;
    out["ratio_cpu"] = ratioCpu;
    std::printf("scene %s (%dx%d, %d spp per run, best of %d; built for -march=%s)\n",
                o.scene.c_str(), o.width, o.height, o.spp, o.repeats, PARTITA_EVAL_MARCH);
    std::printf("  %-34s %12.3f M rays/s (1 thread; %.3f per CPU second)\n",
                "embree rtcIntersect1 incoherent", embree.wall / 1e6, embree.cpu / 1e6);
    std::printf("  %-34s %12.3f M rays/s (1 thread; %.3f per CPU second)\n",
                "path tracer (all rays)", one.rays.wall / 1e6, one.rays.cpu / 1e6);
    std::printf("  %-34s %12.3f  (target >= 0.6; median of %d rounds; %.3f by CPU time)\n",
                "ratio pt / embree", ratio, o.repeats, ratioCpu);
    std::printf("  %-34s", "  rounds");
    for (double r : roundRatios) std::printf(" %.3f", r);
    std::printf("\n");
    // Thread scaling by wall clock. The CPU-time figure says how much of a shortfall is the
    // threads' own doing (contention, false sharing: fewer samples per CPU second) and how much
    // is a busy machine (threads waiting for a core).
    nlohmann::json threads = nlohmann::json::array();
    Rate base = one.samples;
    for (int n : counts) {
        PtMeasurement m = n == 1 ? one : measurePathTracer(scene, o, n, o.repeats);
        threads.push_back({{"n", n},
                           {"samples_per_s", m.samples.wall},
                           {"speedup", m.samples.wall / base.wall},
                           {"samples_per_cpu_s", m.samples.cpu},
                           {"cpu_efficiency", m.samples.cpu / base.cpu}});
        std::printf(
            "  threads %-3d %12.3f M samples/s   speedup %.2fx  (per CPU second: %.2f of 1 "
            "thread's)\n",
            n, m.samples.wall / 1e6, m.samples.wall / base.wall, m.samples.cpu / base.cpu);
    }
    out["threads"] = threads;
    return out;
}

}  // namespace partita::eval
