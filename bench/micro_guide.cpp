// Micro-benchmarks of the guide buffers of `guided` (core/guide): the G-buffer's primary-ray
// pass and the joint denoiser of the per-partition pre-pass images, at 1280x720 on
// cornell-glass, on 1 and 2 threads. Target (issue #13): 11 partitions (K = 10 and the
// complement) denoised in under 1 s on 2 cores.
#include <benchmark/benchmark.h>

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "camera.h"
#include "gltf/gltf_loader.h"
#include "guide/denoise.h"
#include "guide/gbuffer.h"
#include "guide/support_mask.h"
#include "render_scene.h"
#include "renderer.h"
#include "rng.h"
#include "thread_pool.h"

namespace partita {
namespace {

constexpr int kWidth = 1280, kHeight = 720, kPartitions = 11;

const RenderScene& cornellGlass() {
    static RenderScene scene(
        loadGltfFile(std::string(PARTITA_SCENES_DIR) + "/cornell-glass/cornell-glass.gltf"));
    return scene;
}

GBuffer gbufferOf(const RenderScene& scene, ThreadPool& pool) {
    Camera camera(resolveCamera(scene.data(), ""), kWidth, kHeight);
    RenderSettings settings;
    settings.width = kWidth;
    settings.height = kHeight;
    std::atomic<bool> cancel{false};
    RenderObserver observer;
    return buildGBuffer({scene, camera, settings, pool, cancel, observer});
}

void BM_BuildGBuffer(benchmark::State& state) {
    const RenderScene& scene = cornellGlass();
    ThreadPool pool(int(state.range(0)));
    size_t bytes = 0;
    for (auto _ : state) {
        GBuffer g = gbufferOf(scene, pool);
        bytes = g.bytes();
        benchmark::DoNotOptimize(g.texels().data());
    }
    state.counters["gbuffer_MB"] = double(bytes) / 1e6;
    state.SetItemsProcessed(state.iterations() * kWidth * kHeight);
}
BENCHMARK(BM_BuildGBuffer)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_DenoisePartitions(benchmark::State& state) {
    const RenderScene& scene = cornellGlass();
    ThreadPool pool(int(state.range(0)));
    static GBuffer g = gbufferOf(scene, pool);
    // Pre-pass-like images: half B's ~6.5 10^5 records (10^5 samples, ~13 records each, half
    // of them) over 0.9 M pixels and 11 partitions: a record in ~6% of a partition's pixels,
    // zero elsewhere. (The filter's cost does not depend on the values.)
    std::vector<std::vector<float>> images(size_t(state.range(1)),
                                           std::vector<float>(size_t(kWidth) * kHeight, 0.0f));
    Rng rng(1, 2);
    for (auto& image : images)
        for (float& v : image)
            if (rng.nextFloat() < 0.06f) v = 10 * rng.nextFloat();
    size_t bytes = 0, maskBytes = 0;
    for (auto _ : state) {
        std::vector<std::vector<float>> d = denoisePartitions(g, images, {}, &pool);
        bytes = 0;
        for (const auto& image : d) bytes += image.size() * sizeof(float);
        state.PauseTiming();
        maskBytes = SupportMasks(d, kWidth, kHeight, 0.01f).bytes();
        state.ResumeTiming();
        benchmark::DoNotOptimize(d.data());
    }
    state.counters["gbuffer_MB"] = double(g.bytes()) / 1e6;
    state.counters["denoised_float_MB"] = double(bytes) / 1e6;
    state.counters["masks_MB"] = double(maskBytes) / 1e6;
    state.SetItemsProcessed(state.iterations() * kWidth * kHeight);
}
// Arguments: threads, partitions.
BENCHMARK(BM_DenoisePartitions)
    ->Args({1, kPartitions})
    ->Args({2, kPartitions})
    ->Args({2, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace partita
