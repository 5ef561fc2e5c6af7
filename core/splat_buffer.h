// Splats that land anywhere on the film (light tracing; the MCMC chains add theirs to the film
// directly, chain_runner.h), gathered and added in a way that keeps float sums accurate and
// deterministic.
//
// Why: a pixel that light tracing hits from every light path (a point light seen directly, a
// bright caustic) receives millions of tiny splats. Added one by one into a float sum, each
// addition rounds to the ulp of an ever larger total, and the pixel drifts by percents (measured:
// 10% on a directly visible point light at 1024 spp). So splats are buffered for one group (one
// sample index of every pixel), sorted by pixel with a stable counting sort, summed per
// (pixel, type) in double, and each sum is added to the film once: a pixel's float sum then
// takes one addition per group, like a camera film's sample, whatever the splat count.
// The order of everything depends only on the order of add() calls, so the result is
// deterministic when the caller adds in a fixed order.
#pragma once

#include <cstdint>
#include <vector>

#include "math/vec.h"
#include "path_type.h"

namespace partita {

class Film;

class SplatBuffer {
  public:
    SplatBuffer(int width, int height) : width_(width), height_(height) {}

    /// `value` at raster position r, spread by the tent filter (tent_filter.h).
    void addTent(Vec2f r, PathType type, Rgb value);
    /// Adds the buffered splats to `film` (see above), and the same sums to `also` when given
    /// (a combined-only film of the same size), and empties the buffer.
    void flushInto(Film& film, Film* also = nullptr);
    size_t size() const { return splats_.size(); }

  private:
    struct PixelSplat {
        uint32_t pixel;
        PathType type;
        Rgb value;
    };
    /// sorted_: splats_ stably sorted by pixel.
    void sortByPixel();
    int width_, height_;
    std::vector<PixelSplat> splats_, sorted_;
    std::vector<uint32_t> starts_;  // counting sort: next free index of each pixel in sorted_
};

}  // namespace partita
