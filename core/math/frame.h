// An orthonormal basis around a normal. BSDFs work in this local frame: z is the normal.
#pragma once

#include "math/vec.h"

namespace partita {

struct Frame {
    Vec3f s, t, n;

    Frame() : s(1, 0, 0), t(0, 1, 0), n(0, 0, 1) {}
    Frame(Vec3f s_, Vec3f t_, Vec3f n_) : s(s_), t(t_), n(n_) {}

    /// Branchless basis from a unit normal (Duff et al. 2017, "Building an Orthonormal Basis,
    /// Revisited").
    static Frame fromNormal(Vec3f n) {
        float sign = std::copysign(1.0f, n.z);
        float a = -1.0f / (sign + n.z);
        float b = n.x * n.y * a;
        Vec3f s(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
        Vec3f t(b, sign + n.y * n.y * a, -n.y);
        return {s, t, n};
    }

    Vec3f toLocal(Vec3f v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    Vec3f toWorld(Vec3f v) const { return s * v.x + t * v.y + n * v.z; }
};

// Helpers for directions expressed in a local shading frame (z = normal).
inline float cosTheta(Vec3f w) { return w.z; }
inline float absCosTheta(Vec3f w) { return std::abs(w.z); }
inline bool sameHemisphere(Vec3f a, Vec3f b) { return a.z * b.z > 0; }

}  // namespace partita
