// Rough dielectric interface: GGX microfacet reflection and transmission (Walter et al. 2007,
// "Microfacet Models for Refraction through Rough Surfaces") with the exact dielectric Fresnel
// and height-correlated Smith masking, sampled from the visible normals (Heitz 2018). For
// frosted glass and rough water.
//
// `eta` = n(inside) / n(outside), inside being the side opposite the normal. wo.z < 0 means the
// path is inside the medium: the relative index is inverted (etap = 1 / eta). `tint` scales
// transmission only. In radiance transport the transmitted f is divided by etap^2 (etap = index
// on wi's side over index on wo's side); in importance transport it is not, which makes
// f_importance(wo, wi) = f_radiance(wi, wo), the adjoint.
#pragma once

#include <optional>

#include "bsdfs/lobe.h"
#include "bsdfs/microfacet.h"
#include "math/frame.h"

namespace partita {

struct DielectricLobe {
    float eta = 1.5f;
    float alpha = 0.1f;  // GGX alpha (glTF: roughness^2), clamped to kMinAlpha
    Rgb tint{1.0f};

    Rgb eval(Vec3f wo, Vec3f wi, TransportMode mode) const;
    float pdf(Vec3f wo, Vec3f wi) const;
    std::optional<BsdfSample> sample(Vec3f wo, float uc, Vec2f u, TransportMode mode) const;
    bool isDelta() const { return false; }
    Rgb albedo() const { return tint; }
};

}  // namespace partita
