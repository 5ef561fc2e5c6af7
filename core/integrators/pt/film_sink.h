// The path tracer's contribution sink: every complete path of one pixel goes to that pixel of
// the film, under its path type. Not a ContributionSink: samplePath is compiled for this class
// directly, so adding a contribution is an inlined call, not a virtual one.
#pragma once

#include "film.h"
#include "integrators/contribution_key.h"
#include "integrators/pt/path_sampler.h"

namespace partita {

class FilmSink {
  public:
    /// Pixel (x, y) must lie inside the film; `key` (when not null) keeps and renames
    /// contributions (contribution_key.h).
    FilmSink(Film& film, int x, int y, const ContributionKey* key = nullptr)
        : pixel_(film.pixel(x, y)), key_(key) {}
    void add(PathType type, Rgb value) {
        if (key_ && !(*key_)(type)) return;
        pixel_.add(type, value);
    }
    void add(const PathContribution& c) { add(c.type, c.value); }

  private:
    Film::Pixel pixel_;
    const ContributionKey* key_;
};

}  // namespace partita
