// The path tracer's contribution sink: every complete path of one pixel goes to that pixel of
// the film, under its path type. Not a ContributionSink: samplePath is compiled for this class
// directly, so adding a contribution is an inlined call, not a virtual one.
#pragma once

#include "film.h"
#include "integrators/pt/path_sampler.h"

namespace partita {

class FilmSink {
  public:
    /// Pixel (x, y) must lie inside the film.
    FilmSink(Film& film, int x, int y) : pixel_(film.pixel(x, y)) {}
    void add(PathType type, Rgb value) { pixel_.add(type, value); }
    void add(const PathContribution& c) { add(c.type, c.value); }

  private:
    Film::Pixel pixel_;
};

}  // namespace partita
