// The size distributions of Veach's perturbations (Veach 1997, sec. 11.4.3): a displacement on
// the image plane for the lens and multi-chain perturbations, a deflection angle for the caustic
// and multi-chain ones. Both are exponential between a smallest and a largest size, so small
// and large steps are tried alike (the density of the size s is 1 / (s ln(s2/s1)), uniform in
// log s), in a direction uniform around the current one. Both proposals are symmetric: the
// density of moving from a to b depends only on their distance (or angle), so it cancels in the
// acceptance ratio T(y->x) / T(x->y), leaving only the Jacobians of what follows.
#pragma once

#include "math/vec.h"

namespace partita {

struct PerturbationRange {
    float smallest = 0, largest = 0;  // s1 < s2, both > 0
};

/// s = s2 (s1/s2)^u for u uniform in [0, 1): log-uniform in [s1, s2].
float perturbationSize(const PerturbationRange& range, float u);
/// The density of the size s: 1 / (s ln(s2/s1)) inside [s1, s2], else 0.
float perturbationSizeDensity(const PerturbationRange& range, float s);

/// A raster offset of size perturbationSize(range, u.x) at angle 2 pi u.y.
Vec2f perturbRaster(Vec2f raster, const PerturbationRange& range, Vec2f u);

/// The unit direction w turned by the angle perturbationSize(range, u.x) (radians, below pi)
/// about w, at azimuth 2 pi u.y.
Vec3f perturbDirection(Vec3f w, const PerturbationRange& range, Vec2f u);

}  // namespace partita
