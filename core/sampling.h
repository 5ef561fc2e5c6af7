// Warping functions from the unit square to common domains, with their densities. The warps a
// path tracer calls at every vertex are inline. Discrete choices (lights) use AliasTable.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "math/vec.h"

namespace partita {

namespace detail {
/// `c ? a : b` without a branch. GCC compiles a float ?: into a jump, which costs a
/// misprediction half of the time when the condition is a coin flip per sample (which half of
/// a warp's domain a random number falls in); these masks cannot mispredict.
inline float select(bool c, float a, float b) {
    uint32_t mask = 0u - uint32_t(c);
    return std::bit_cast<float>((std::bit_cast<uint32_t>(a) & mask) |
                                (std::bit_cast<uint32_t>(b) & ~mask));
}

/// sin and cos of x in [-pi/4, pi/4]: the minimax polynomials of Cephes' sinf/cosf, within about
/// one float ulp of std::sin/std::cos there. The disk mapping needs no more than this interval,
/// so it skips libm's range reduction and call (one per path vertex).
inline void sinCosQuarterPi(float x, float& s, float& c) {
    float z = x * x;
    s = ((-1.9515295891e-4f * z + 8.3321608736e-3f) * z - 1.6666654611e-1f) * z * x + x;
    c = ((2.443315711809948e-5f * z - 1.388731625493765e-3f) * z + 4.166664568298827e-2f) * z * z -
        0.5f * z + 1.0f;
}
}  // namespace detail

/// Concentric mapping of the square to the unit disk (Shirley & Chiu 1997).
inline Vec2f sampleConcentricDisk(Vec2f u) {
    float ox = 2 * u.x - 1, oy = 2 * u.y - 1;
    if (ox == 0 && oy == 0) return {0, 0};
    // Which axis dominates is a coin flip per sample, so this selects instead of branching.
    // |ox| > |oy|: r = ox, theta = phi = pi/4 (oy / ox), in [-pi/4, pi/4].
    // Otherwise:   r = oy, theta = pi/2 - phi with phi = pi/4 (ox / oy), so that
    //              cos(theta) = sin(phi) and sin(theta) = cos(phi).
    bool xMajor = std::abs(ox) > std::abs(oy);
    float r = detail::select(xMajor, ox, oy), t = detail::select(xMajor, oy, ox);
    float s, c;
    detail::sinCosQuarterPi((kPi / 4) * (t / r), s, c);
    return {r * detail::select(xMajor, c, s), r * detail::select(xMajor, s, c)};
}

/// Cosine-weighted hemisphere around +z (Malley's method); pdf = cos(theta) / pi.
inline Vec3f sampleCosineHemisphere(Vec2f u) {
    Vec2f d = sampleConcentricDisk(u);
    float z = safeSqrt(1 - d.x * d.x - d.y * d.y);
    return {d.x, d.y, z};
}
inline float cosineHemispherePdf(float cosTheta) { return cosTheta > 0 ? cosTheta * kInvPi : 0; }

Vec3f sampleUniformSphere(Vec2f u);
constexpr float uniformSpherePdf() { return 1.0f / (4.0f * kPi); }

/// Uniform directions in the cone around +z with cos(theta) >= cosThetaMax.
Vec3f sampleUniformCone(Vec2f u, float cosThetaMax);
inline float uniformConePdf(float cosThetaMax) {
    return 1.0f / (2.0f * kPi * (1.0f - cosThetaMax));
}

/// Uniform barycentrics (b0, b1) on a triangle; b2 = 1 - b0 - b1 (Heitz 2019, low distortion).
inline Vec2f sampleUniformTriangle(Vec2f u) {
    // u.x < u.y: b0 = u.x / 2, b1 = u.y - b0; otherwise b1 = u.y / 2, b0 = u.x - b1. Selects, not
    // branches: the comparison is a coin flip per sample.
    bool lower = u.x < u.y;
    float half = detail::select(lower, u.x, u.y) / 2;
    return {detail::select(lower, half, u.x - half), detail::select(lower, u.y - half, half)};
}

/// Tent filter of radius 1 sampled exactly: returns an offset in [-1, 1] with density 1 - |x|.
inline float sampleTent(float u) {
    // Inverse CDF of the tent on [-1, 1], one half at a time: u < 1/2 gives -1 + sqrt(2 u),
    // otherwise 1 - sqrt(2 - 2 u).
    bool left = u < 0.5f;
    float a = std::sqrt(detail::select(left, 2 * u, 2 - 2 * u));
    return detail::select(left, a - 1, 1 - a);
}

/// Veach's power heuristic with beta = 2, written for two strategies.
inline float powerHeuristic(float pdfA, float pdfB) {
    float a = pdfA * pdfA, b = pdfB * pdfB;
    if (std::isinf(a)) return 1.0f;
    return a + b > 0 ? a / (a + b) : 0.0f;
}

}  // namespace partita
