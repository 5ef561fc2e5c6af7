#include "bsdfs/microfacet.h"

#include <cmath>

namespace partita {

float TrowbridgeReitz::D(Vec3f wm) const {
    if (wm.z <= 0) return 0;
    // D = a^2 / (pi (cos^2 (a^2 - 1) + 1)^2); for a unit wm the bracket is
    // sin^2 + a^2 cos^2, written so that it keeps precision when wm is close to z.
    float a2 = alpha_ * alpha_;
    float sin2 = wm.x * wm.x + wm.y * wm.y;
    float denom = sin2 + a2 * wm.z * wm.z;
    if (denom <= 0) return 0;
    return a2 / (kPi * denom * denom);
}

float TrowbridgeReitz::lambda(Vec3f w) const {
    float cos2 = w.z * w.z;
    if (cos2 == 0) return kInf;
    float a2Tan2 = alpha_ * alpha_ * (w.x * w.x + w.y * w.y) / cos2;
    if (std::isinf(a2Tan2)) return kInf;
    // (sqrt(1 + x) - 1) / 2 rewritten as x / (2 (sqrt(1 + x) + 1)) to avoid cancellation.
    return a2Tan2 / (2 * (std::sqrt(1 + a2Tan2) + 1));
}

float TrowbridgeReitz::visibleNormalPdf(Vec3f w, Vec3f wm) const {
    float cosW = std::abs(w.z);
    if (cosW == 0) return 0;
    if (w.z < 0) w = -w;
    float cosWm = dot(w, wm);
    if (cosWm <= 0) return 0;
    return G1(w) * cosWm * D(wm) / cosW;
}

Vec3f TrowbridgeReitz::sampleVisibleNormal(Vec3f w, Vec2f u) const {
    if (w.z < 0) w = -w;
    // Stretch the view direction so that the ellipsoid of normals becomes the unit hemisphere.
    Vec3f wh = normalize(Vec3f(alpha_ * w.x, alpha_ * w.y, w.z));
    // Orthonormal basis around wh; any tangent works when wh is the pole.
    float lenSq = wh.x * wh.x + wh.y * wh.y;
    Vec3f t1 = lenSq > 0 ? Vec3f(-wh.y, wh.x, 0) / std::sqrt(lenSq) : Vec3f(1, 0, 0);
    Vec3f t2 = cross(wh, t1);
    // A uniform point on the unit disk, then squash the half of the disk that the hemisphere's
    // silhouette hides when seen from wh (the projected area of the visible hemisphere).
    float r = std::sqrt(u.x);
    float phi = 2 * kPi * u.y;
    float p1 = r * std::cos(phi), p2 = r * std::sin(phi);
    float s = 0.5f * (1 + wh.z);
    p2 = (1 - s) * safeSqrt(1 - p1 * p1) + s * p2;
    // Lift onto the hemisphere and unstretch back to the ellipsoid.
    Vec3f nh = t1 * p1 + t2 * p2 + wh * safeSqrt(1 - p1 * p1 - p2 * p2);
    Vec3f wm(alpha_ * nh.x, alpha_ * nh.y, std::max(1e-7f, nh.z));
    return normalize(wm);
}

}  // namespace partita
