// The GGX / Trowbridge-Reitz microfacet distribution (isotropic), Smith's masking-shadowing
// (height-correlated form), and sampling of the distribution of visible normals (Heitz 2018,
// "Sampling the GGX Distribution of Visible Normals", JCGT 7(4)). All in the local frame,
// z = macro-surface normal; microfacet normals wm always have wm.z > 0.
#pragma once

#include "math/frame.h"
#include "math/vec.h"

namespace partita {

/// Below this alpha the GGX lobe is clamped: the densities reach ~1e6 per steradian and float
/// round-off in half vectors starts to dominate. Materials this smooth are mapped to Dirac lobes
/// (material_mapping.h), so the clamp only touches roughness in [0.02, 0.032).
constexpr float kMinAlpha = 1e-3f;

class TrowbridgeReitz {
  public:
    explicit TrowbridgeReitz(float alpha) : alpha_(std::max(alpha, kMinAlpha)) {}

    float alpha() const { return alpha_; }

    /// Normal distribution D(wm): density of microfacet normals per unit projected area
    /// (integral of D(wm) cos(theta_m) over the hemisphere is 1).
    float D(Vec3f wm) const;
    /// Smith's auxiliary function Lambda(w).
    float lambda(Vec3f w) const;
    /// Masking of one direction, G1(w) = 1 / (1 + Lambda(w)).
    float G1(Vec3f w) const { return 1 / (1 + lambda(w)); }
    /// Height-correlated masking-shadowing, G(wo, wi) = 1 / (1 + Lambda(wo) + Lambda(wi)).
    float G(Vec3f wo, Vec3f wi) const { return 1 / (1 + lambda(wo) + lambda(wi)); }

    /// Density of normals visible from w: D_w(wm) = G1(w) max(0, w.wm) D(wm) / |cos(theta_w)|,
    /// where w below the surface is treated as its mirror image -w (the distribution is
    /// symmetric), so this is the density sampleVisibleNormal(w, .) draws from.
    float visibleNormalPdf(Vec3f w, Vec3f wm) const;
    /// Draw wm from D_w (Heitz 2018). `w` may be on either side; wm.z > 0 always.
    Vec3f sampleVisibleNormal(Vec3f w, Vec2f u) const;

  private:
    float alpha_;
};

}  // namespace partita
