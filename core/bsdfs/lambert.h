// Ideal diffuse reflection: f = R / pi on the upper hemisphere, cosine-weighted sampling.
// Opaque: nothing is returned when wo or wi is below the surface (Bsdf makes surfaces
// two-sided by mirroring the frame before the lobe sees the directions).
#pragma once

#include <optional>

#include "bsdfs/lobe.h"
#include "math/frame.h"
#include "sampling.h"

namespace partita {

struct LambertLobe {
    Rgb reflectance{0.5f};

    Rgb eval(Vec3f wo, Vec3f wi, TransportMode) const {
        if (wo.z <= 0 || wi.z <= 0) return Rgb(0.0f);
        return reflectance * kInvPi;
    }
    float pdf(Vec3f wo, Vec3f wi) const {
        if (wo.z <= 0 || wi.z <= 0) return 0;
        return cosineHemispherePdf(wi.z);
    }
    std::optional<BsdfSample> sample(Vec3f wo, float, Vec2f u, TransportMode) const {
        if (wo.z <= 0) return std::nullopt;
        Vec3f wi = sampleCosineHemisphere(u);
        if (wi.z <= 0) return std::nullopt;  // the disk's rim maps onto the horizon
        BsdfSample s;
        s.f = reflectance * kInvPi;
        s.wi = wi;
        s.pdf = cosineHemispherePdf(wi.z);
        return s;
    }
    bool isDelta() const { return false; }
    Rgb albedo() const { return reflectance; }
};

}  // namespace partita
