// Rays and robust ray origins. Inline: a path tracer offsets three points per path vertex.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

#include "math/vec.h"

namespace partita {

struct Ray {
    Vec3f o, d;
    float tMax = kInf;
};

namespace detail {
// Four-lane vectors (GCC and Clang vector extensions; SSE registers on x86-64): the three
// coordinates of a ray origin are offset at once rather than one at a time.
using Float4 = float __attribute__((vector_size(16)));
using Int4 = int32_t __attribute__((vector_size(16)));
}  // namespace detail

/// Offset a surface point along its geometric normal, to the side `w` leaves towards, far enough
/// that the new ray does not re-hit the surface it starts on. Integer-ULP scheme of Wachter and
/// Binder (Ray Tracing Gems, ch. 6): scales with the magnitude of the coordinates, so it is
/// robust both near the origin and far from it.
inline Vec3f offsetRayOrigin(Vec3f p, Vec3f ng, Vec3f w) {
    using detail::Float4, detail::Int4;
    constexpr float kOrigin = 1.0f / 32.0f;
    constexpr float kFloatScale = 1.0f / 65536.0f;
    constexpr float kIntScale = 256.0f;
    Vec3f n = dot(ng, w) < 0 ? -ng : ng;
    Float4 p4 = {p.x, p.y, p.z, 0}, n4 = {n.x, n.y, n.z, 0};
    // Per coordinate: far from zero, move p by a number of ulps proportional to n (away from
    // zero when n and p have the same sign); near zero, where ulps are tiny, by a fixed amount.
    // Both are computed and selected per lane, without branches.
    Int4 ofi = __builtin_convertvector(kIntScale * n4, Int4);
    Int4 far = std::bit_cast<Int4>(p4) + (p4 < 0 ? -ofi : ofi);
    Int4 near = std::bit_cast<Int4>(p4 + kFloatScale * n4);
    Int4 absBits = std::bit_cast<Int4>(p4) & 0x7fffffff;
    Float4 o = std::bit_cast<Float4>(std::bit_cast<Float4>(absBits) < kOrigin ? near : far);
    return {o[0], o[1], o[2]};
}

/// A ray from p (offset) towards direction d.
inline Ray spawnRay(Vec3f p, Vec3f ng, Vec3f d) { return {offsetRayOrigin(p, ng, d), d, kInf}; }

/// The shadow ray segment from the offset origin `from` (of point p) to q, offset on p's side of
/// its normal ngQ. tMax is just below 1 so that q's own surface does not occlude; d is
/// unnormalised.
inline Ray shadowRayFrom(Vec3f from, Vec3f p, Vec3f q, Vec3f ngQ) {
    Vec3f to = offsetRayOrigin(q, ngQ, p - q);
    return {from, to - from, 1.0f - 1e-4f};
}

/// A shadow ray segment from p to q, both offset, for occlusion queries (see shadowRayFrom).
inline Ray spawnShadowRay(Vec3f p, Vec3f ngP, Vec3f q, Vec3f ngQ) {
    return shadowRayFrom(offsetRayOrigin(p, ngP, q - p), p, q, ngQ);
}

/// offsetRayOrigin for the rays that leave one surface point (a path vertex's shadow ray and
/// continuation): the offset point depends only on the side of ng a ray leaves towards, so each
/// side is computed once, when first needed.
class RayOrigins {
  public:
    RayOrigins(Vec3f p, Vec3f ng) : p_(p), ng_(ng) {}
    /// offsetRayOrigin(p, ng, w).
    Vec3f towards(Vec3f w) {
        int side = dot(ng_, w) < 0 ? 1 : 0;
        if (!known_[side]) {
            origin_[side] = offsetRayOrigin(p_, ng_, w);
            known_[side] = true;
        }
        return origin_[side];
    }

  private:
    Vec3f p_, ng_;
    Vec3f origin_[2];
    bool known_[2] = {false, false};
};

}  // namespace partita
