// The path tracer's contribution sink: every complete path of one pixel goes to that pixel of
// the film, under its path type. Not a ContributionSink: samplePath is compiled for this class
// directly, so adding a contribution is an inlined call, not a virtual one.
#pragma once

#include "film.h"
#include "integrators/pt/path_sampler.h"

namespace partita {

class FilmSink {
public:
    FilmSink(Film& film, int x, int y) : film_(film), x_(x), y_(y) {}
    void add(PathType type, Rgb value) { film_.addSample(x_, y_, type, value); }
    void add(const PathContribution& c) { add(c.type, c.value); }

private:
    Film& film_;
    int x_, y_;
};

}  // namespace partita
