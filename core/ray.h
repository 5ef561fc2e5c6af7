// Rays and robust ray origins.
#pragma once

#include "math/vec.h"

namespace partita {

struct Ray {
    Vec3f o, d;
    float tMax = kInf;
};

/// Offset a surface point along its geometric normal, to the side `w` leaves towards, far enough
/// that the new ray does not re-hit the surface it starts on. Integer-ULP scheme of Wachter and
/// Binder (Ray Tracing Gems, ch. 6): scales with the magnitude of the coordinates, so it is
/// robust both near the origin and far from it.
Vec3f offsetRayOrigin(Vec3f p, Vec3f ng, Vec3f w);

/// A ray from p (offset) towards direction d.
inline Ray spawnRay(Vec3f p, Vec3f ng, Vec3f d) { return {offsetRayOrigin(p, ng, d), d, kInf}; }

/// A shadow ray segment from p to q, both offset, for occlusion queries. tMax is just below 1
/// so that q's own surface does not occlude; d is unnormalised (q - p).
Ray spawnShadowRay(Vec3f p, Vec3f ngP, Vec3f q, Vec3f ngQ);

}  // namespace partita
