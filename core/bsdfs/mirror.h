// A perfect mirror (Dirac delta) for smooth metals. Its reflectance is Schlick's Fresnel with
// F0 = tint, the same Fresnel as ConductorLobe, so that a conductor's roughness going to zero
// converges to this lobe. Opaque: nothing below the surface.
#pragma once

#include <optional>

#include "bsdfs/fresnel.h"
#include "bsdfs/lobe.h"
#include "math/frame.h"

namespace partita {

struct MirrorLobe {
    Rgb tint{1.0f};  // F0 of Schlick's Fresnel

    Rgb eval(Vec3f, Vec3f, TransportMode) const { return Rgb(0.0f); }
    float pdf(Vec3f, Vec3f) const { return 0; }
    std::optional<BsdfSample> sample(Vec3f wo, float, Vec2f, TransportMode) const {
        if (wo.z <= 0) return std::nullopt;
        BsdfSample s;
        s.wi = Vec3f(-wo.x, -wo.y, wo.z);
        s.f = fresnelSchlick(wo.z, tint) / wo.z;  // weight F, divided by |cos(wi)| = cos(wo)
        s.pdf = 1;
        s.isDelta = true;
        return s;
    }
    bool isDelta() const { return true; }
    Rgb albedo() const { return tint; }
};

}  // namespace partita
