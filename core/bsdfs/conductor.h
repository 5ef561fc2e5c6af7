// Rough conductor: a GGX microfacet BRDF (Walter et al. 2007; Heitz 2014 height-correlated
// Smith masking) with Schlick's Fresnel, F0 = tint, as glTF's metal model prescribes. Sampled
// from the visible normals (Heitz 2018). Opaque: nothing below the surface.
//
// DiffuseConductorMixLobe is glTF's metallic blend, (1 - m) Lambert + m Conductor, for metallic
// values between 0 and 1 (texture edges, partially metallic materials). It picks the lobe to
// sample with probability m and returns the full mixture's f and pdf.
#pragma once

#include <optional>

#include "bsdfs/lambert.h"
#include "bsdfs/lobe.h"
#include "bsdfs/microfacet.h"
#include "math/frame.h"

namespace partita {

struct ConductorLobe {
    Rgb f0{1.0f};        // Schlick's F0 (glTF: base colour)
    float alpha = 0.1f;  // GGX alpha (glTF: roughness^2), clamped to kMinAlpha

    Rgb eval(Vec3f wo, Vec3f wi, TransportMode mode) const;
    float pdf(Vec3f wo, Vec3f wi) const;
    std::optional<BsdfSample> sample(Vec3f wo, float uc, Vec2f u, TransportMode mode) const;
    bool isDelta() const { return false; }
    Rgb albedo() const { return f0; }
};

struct DiffuseConductorMixLobe {
    LambertLobe diffuse;
    ConductorLobe conductor;
    float metallic = 0.5f;  // weight of the conductor, in [0, 1]

    Rgb eval(Vec3f wo, Vec3f wi, TransportMode mode) const;
    float pdf(Vec3f wo, Vec3f wi) const;
    std::optional<BsdfSample> sample(Vec3f wo, float uc, Vec2f u, TransportMode mode) const;
    bool isDelta() const { return false; }
    Rgb albedo() const { return diffuse.albedo() * (1 - metallic) + conductor.albedo() * metallic; }
};

}  // namespace partita
