// The path tracer's contribution sink: every complete path of one pixel goes to that pixel of
// the film, under its path type. Not a ContributionSink: samplePath is compiled for this class
// directly, so adding a contribution is an inlined call, not a virtual one.
#pragma once

#include <cstdint>
#include <optional>

#include "film.h"
#include "integrators/contribution_key.h"
#include "integrators/pt/path_sampler.h"

namespace partita {

class FilmSink {
  public:
    /// Pixel (x, y) must lie inside the film; `key` (when not null) keeps and renames
    /// contributions (contribution_key.h). With an `oddHalf` film (combined-only, the same
    /// size), the contributions of odd sample indices (selectSample) go there too: the error
    /// estimate's half B (sample_passes.h).
    FilmSink(Film& film, int x, int y, const ContributionKey* key = nullptr,
             Film* oddHalf = nullptr)
        : pixel_(film.pixel(x, y)), key_(key) {
        if (oddHalf) oddPixel_.emplace(oddHalf->pixel(x, y));
    }
    /// The sample index whose path comes next.
    void selectSample(uint64_t sample) {
        sample_ = sample;
        odd_ = oddPixel_ && (sample & 1);
    }
    void add(PathType type, Rgb value) {
        if (key_ && !(*key_)(type, sample_)) return;
        pixel_.add(type, value);
        if (odd_) oddPixel_->add(type, value);
    }
    void add(const PathContribution& c) { add(c.type, c.value); }

  private:
    Film::Pixel pixel_;
    std::optional<Film::Pixel> oddPixel_;
    const ContributionKey* key_;
    uint64_t sample_ = 0;
    bool odd_ = false;
};

}  // namespace partita
