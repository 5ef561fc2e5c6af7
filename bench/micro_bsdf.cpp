// Micro-benchmarks of BSDF sampling and evaluation (the path tracer's shading hot path).
#include <benchmark/benchmark.h>

#include "bsdf.h"
#include "material_mapping.h"
#include "rng.h"

namespace partita {
namespace {

Bsdf bsdfFor(float metallic, float roughness, float transmission) {
    Material m;
    m.baseColor = Rgb(0.7f);
    m.metallic = metallic;
    m.roughness = roughness;
    m.transmission = transmission;
    SurfacePoint sp;
    return makeBsdf(m, {}, sp);
}

void sampleAndEval(benchmark::State& state, Bsdf bsdf) {
    Rng rng(1, 2);
    Vec3f wo = normalize(Vec3f(0.3f, 0.2f, 0.9f));
    for (auto _ : state) {
        auto s = bsdf.sample(wo, rng.nextFloat(), {rng.nextFloat(), rng.nextFloat()});
        if (s) benchmark::DoNotOptimize(bsdf.eval(wo, s->wi) + Rgb(bsdf.pdf(wo, s->wi)));
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_Lambert(benchmark::State& s) { sampleAndEval(s, bsdfFor(0, 1, 0)); }
void BM_GgxConductor(benchmark::State& s) { sampleAndEval(s, bsdfFor(1, 0.3f, 0)); }
void BM_GgxDielectric(benchmark::State& s) { sampleAndEval(s, bsdfFor(0, 0.3f, 1)); }
void BM_SmoothDielectric(benchmark::State& s) { sampleAndEval(s, bsdfFor(0, 0, 1)); }
BENCHMARK(BM_Lambert);
BENCHMARK(BM_GgxConductor);
BENCHMARK(BM_GgxDielectric);
BENCHMARK(BM_SmoothDielectric);

}  // namespace
}  // namespace partita
