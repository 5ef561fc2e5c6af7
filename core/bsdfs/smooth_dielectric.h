// A smooth dielectric interface (Dirac delta): specular reflection with probability F and
// refraction with probability 1 - F (exact Fresnel), for glass and water. `eta` is
// n(inside) / n(outside), the inside being the side opposite the normal; wo.z < 0 means the path
// is inside and the ratio is inverted. `tint` scales transmission only (glTF: the base colour
// tints the transmitted light, the dielectric's reflection is white). Radiance transport divides
// the transmitted value by etap^2 (radiance is compressed into the denser medium); importance
// transport does not.
#pragma once

#include <optional>

#include "bsdfs/fresnel.h"
#include "bsdfs/lobe.h"
#include "math/frame.h"

namespace partita {

struct SmoothDielectricLobe {
    float eta = 1.5f;
    Rgb tint{1.0f};

    Rgb eval(Vec3f, Vec3f, TransportMode) const { return Rgb(0.0f); }
    float pdf(Vec3f, Vec3f) const { return 0; }
    std::optional<BsdfSample> sample(Vec3f wo, float uc, Vec2f, TransportMode mode) const {
        if (wo.z == 0) return std::nullopt;
        float reflectance = fresnelDielectric(wo.z, eta);
        BsdfSample s;
        s.isDelta = true;
        // Branch probabilities are proportional to the untinted weights F and 1 - F.
        if (uc < reflectance) {
            s.wi = Vec3f(-wo.x, -wo.y, wo.z);
            s.f = Rgb(reflectance / std::abs(wo.z));
            s.pdf = reflectance;
            return s;
        }
        Vec3f wi;
        float etap = 1;
        if (!refract(wo, Vec3f(0, 0, 1), eta, wi, etap)) return std::nullopt;
        if (wi.z == 0) return std::nullopt;
        float transmittance = 1 - reflectance;
        s.wi = wi;
        s.f = tint * (transmittance / std::abs(wi.z));
        if (mode == TransportMode::Radiance) s.f /= etap * etap;
        s.pdf = transmittance;
        s.isTransmission = true;
        s.eta = etap;
        return s;
    }
    bool isDelta() const { return true; }
    Rgb albedo() const { return tint; }
};

}  // namespace partita
