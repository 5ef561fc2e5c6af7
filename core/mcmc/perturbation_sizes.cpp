#include "mcmc/perturbation_sizes.h"

#include <cmath>

#include "math/frame.h"

namespace partita {

float perturbationSize(const PerturbationRange& range, float u) {
    return range.largest * std::pow(range.smallest / range.largest, u);
}

float perturbationSizeDensity(const PerturbationRange& range, float s) {
    if (!(s >= range.smallest && s <= range.largest)) return 0;
    return 1 / (s * std::log(range.largest / range.smallest));
}

Vec2f perturbRaster(Vec2f raster, const PerturbationRange& range, Vec2f u) {
    float r = perturbationSize(range, u.x), phi = 2 * kPi * u.y;
    return {raster.x + r * std::cos(phi), raster.y + r * std::sin(phi)};
}

Vec3f perturbDirection(Vec3f w, const PerturbationRange& range, Vec2f u) {
    float theta = std::min(perturbationSize(range, u.x), kPi), phi = 2 * kPi * u.y;
    float sinTheta = std::sin(theta);
    Vec3f local{sinTheta * std::cos(phi), sinTheta * std::sin(phi), std::cos(theta)};
    return normalize(Frame::fromNormal(w).toWorld(local));
}

}  // namespace partita
