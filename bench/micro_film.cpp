// Micro-benchmark of Film::addSample, called once per path contribution.
#include <benchmark/benchmark.h>

#include "film.h"
#include "rng.h"

namespace partita {
namespace {

void BM_FilmAddSample(benchmark::State& state) {
    Film film(320, 240);
    Rng rng(3, 4);
    PathType types[4] = {PathType().withVertex(false),
                         PathType().withVertex(false).withVertex(false),
                         PathType().withVertex(true).withVertex(false), PathType()};
    for (auto _ : state) {
        uint32_t r = rng.nextUInt();
        film.addSample(int(r % 320), int((r >> 9) % 240), types[r >> 30], Rgb(1.0f));
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FilmAddSample);

}  // namespace
}  // namespace partita
