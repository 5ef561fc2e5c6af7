// The tent filter of radius one pixel that the path tracer draws its camera rays from, as a
// splat: a value landing at raster position r goes to the up to four pixels whose tents cover
// r, pixel (x, y) getting (1 - |dx|)(1 - |dy|) of it, where (dx, dy) is r's offset from the
// pixel's centre. Splatting estimators (light tracing, MLT) use it so that their images are
// filtered like the path tracer's.
#pragma once

#include <cmath>

#include "math/vec.h"

namespace partita {

/// Calls f(x, y, weight) for each pixel of a width x height image that the tent at r covers
/// with a weight > 0 (pixels outside the image are left out).
template <typename F>
inline void forEachTentPixel(Vec2f r, int width, int height, F&& f) {
    float fx = r.x - 0.5f, fy = r.y - 0.5f;
    int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
    float wx1 = fx - float(x0), wy1 = fy - float(y0);
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            int x = x0 + dx, y = y0 + dy;
            if (x < 0 || y < 0 || x >= width || y >= height) continue;
            float w = (dx ? wx1 : 1 - wx1) * (dy ? wy1 : 1 - wy1);
            if (w > 0) f(x, y, w);
        }
}

}  // namespace partita
