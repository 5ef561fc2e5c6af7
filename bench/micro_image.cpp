// Micro-benchmark of encodePng on a preview-sized layer (320x240, the default resolution):
// OpenImageIO's default compression (result previews) against PngOptions::fast (the daemon's
// preview frames, one PNG per path-type layer). Run: partita-bench --benchmark_filter=Png
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "image_io.h"

namespace partita {
namespace {

/// Render-like content: a smooth gradient with per-pixel noise, a third of the rows black (as in
/// the sparse path-type layers).
Image previewLayer(int w, int h) {
    Image img(w, h);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> noise(0.0f, 0.3f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (y % 3 == 2) continue;
            const float base = 0.2f + 0.6f * float(x) / float(w) * float(h - y) / float(h);
            img.set(x, y, Rgb(base * (1.0f + noise(rng)), base * 0.8f, base * 0.5f + noise(rng)));
        }
    return img;
}

void encode(benchmark::State& state, bool fast) {
    const Image img = previewLayer(int(state.range(0)), int(state.range(1)));
    const float exposure = autoExposure(img);
    size_t bytes = 0;
    for (auto _ : state) {
        std::vector<uint8_t> png = encodePng(img, exposure, PngOptions{.fast = fast});
        bytes = png.size();
        benchmark::DoNotOptimize(png.data());
    }
    state.counters["png_bytes"] = double(bytes);
    state.SetItemsProcessed(state.iterations());
}

void BM_EncodePngDefault(benchmark::State& state) { encode(state, false); }
void BM_EncodePngFast(benchmark::State& state) { encode(state, true); }
BENCHMARK(BM_EncodePngDefault)->Args({320, 240})->Args({1280, 720})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EncodePngFast)->Args({320, 240})->Args({1280, 720})->Unit(benchmark::kMillisecond);

void BM_EncodeSrgb8(benchmark::State& state) {
    const Image img = previewLayer(320, 240);
    for (auto _ : state) {
        unsigned sum = 0;
        for (float v : img.rgb) sum += encodeSrgb8(v);
        benchmark::DoNotOptimize(sum);
    }
    state.SetItemsProcessed(state.iterations() * int64_t(img.rgb.size()));
}
BENCHMARK(BM_EncodeSrgb8);

}  // namespace
}  // namespace partita
