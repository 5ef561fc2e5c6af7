// Fresnel reflectance: the exact formula for a dielectric interface, and Schlick's approximation
// that glTF's metallic-roughness model uses for conductors.
#pragma once

#include "math/vec.h"

namespace partita {

/// Unpolarised Fresnel reflectance of a smooth dielectric interface. `cosThetaI` is the cosine
/// between the incident direction and the normal; `eta` = n(side the normal points away from,
/// i.e. inside) / n(side the normal points to, i.e. outside). A negative cosine means the
/// direction is inside, and the ratio is inverted. Returns 1 under total internal reflection.
inline float fresnelDielectric(float cosThetaI, float eta) {
    cosThetaI = clamp(cosThetaI, -1.0f, 1.0f);
    if (cosThetaI < 0) {
        eta = 1 / eta;
        cosThetaI = -cosThetaI;
    }
    float sin2ThetaT = (1 - cosThetaI * cosThetaI) / (eta * eta);
    if (sin2ThetaT >= 1) return 1;
    float cosThetaT = safeSqrt(1 - sin2ThetaT);
    float rParallel = (eta * cosThetaI - cosThetaT) / (eta * cosThetaI + cosThetaT);
    float rPerpendicular = (cosThetaI - eta * cosThetaT) / (cosThetaI + eta * cosThetaT);
    return 0.5f * (rParallel * rParallel + rPerpendicular * rPerpendicular);
}

/// Schlick's approximation F0 + (1 - F0)(1 - cos)^5, per channel.
inline Rgb fresnelSchlick(float cosTheta, Rgb f0) {
    float m = clamp(1 - std::abs(cosTheta), 0.0f, 1.0f);
    float m5 = (m * m) * (m * m) * m;
    return f0 + (Rgb(1.0f) - f0) * m5;
}

/// Mirror `w` about the normal `n` (both pointing away from the surface).
inline Vec3f reflect(Vec3f w, Vec3f n) { return -w + n * (2 * dot(w, n)); }

/// Refract `wi` (pointing away from the surface) through the interface with normal `n` and
/// relative index `eta` = n(inside) / n(outside), where `n` points outside. Handles `wi` on
/// either side. On success writes the transmitted direction (pointing away, on the other side)
/// and `etap` = n(transmitted side) / n(incident side); returns false under total internal
/// reflection.
inline bool refract(Vec3f wi, Vec3f n, float eta, Vec3f& wt, float& etap) {
    float cosThetaI = dot(n, wi);
    if (cosThetaI < 0) {
        eta = 1 / eta;
        cosThetaI = -cosThetaI;
        n = -n;
    }
    float sin2ThetaI = std::max(0.0f, 1 - cosThetaI * cosThetaI);
    float sin2ThetaT = sin2ThetaI / (eta * eta);
    if (sin2ThetaT >= 1) return false;
    float cosThetaT = safeSqrt(1 - sin2ThetaT);
    // Snell's law in vector form: the tangential part scales by 1/eta, the normal part is
    // -cosThetaT along n.
    wt = -wi / eta + n * (cosThetaI / eta - cosThetaT);
    etap = eta;
    return true;
}

}  // namespace partita
