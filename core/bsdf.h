// The BSDF interface every integrator uses. A Bsdf is a value type (no allocation per hit): a
// shading frame plus one of a closed set of lobes held in a std::variant. Directions passed in
// and out are in world space and point away from the surface (wo towards the previous vertex,
// wi towards the next one).
//
// Conventions (pbrt's):
// - eval() returns f(wo, wi) without the cosine; zero for Dirac lobes.
// - pdf() is a solid-angle density over wi; zero for Dirac lobes.
// - sample() returns f and pdf such that f * |cos(wi, n_s)| / pdf is the sample weight. For a
//   Dirac lobe, pdf is the discrete probability of the chosen branch (e.g. reflect vs refract)
//   and f carries the delta's weight divided by |cos|.
// - TransportMode matters for refraction: radiance is scaled by 1/eta^2, importance is not.
#pragma once

#include <optional>
#include <variant>

#include "bsdfs/conductor.h"
#include "bsdfs/dielectric.h"
#include "bsdfs/lambert.h"
#include "bsdfs/lobe.h"
#include "bsdfs/mirror.h"
#include "bsdfs/smooth_dielectric.h"
#include "math/frame.h"
#include "math/vec.h"

namespace partita {

using BsdfLobe = std::variant<LambertLobe, ConductorLobe, DielectricLobe, MirrorLobe,
                              SmoothDielectricLobe, DiffuseConductorMixLobe>;

class Bsdf {
  public:
    Bsdf() = default;
    /// `shading` is the shading frame (z = shading normal), `ng` the geometric normal; both on
    /// the same side.
    Bsdf(const Frame& shading, Vec3f ng, BsdfLobe lobe) : frame_(shading), ng_(ng), lobe_(lobe) {}

    Rgb eval(Vec3f wo, Vec3f wi, TransportMode mode = TransportMode::Radiance) const;
    float pdf(Vec3f wo, Vec3f wi) const;
    std::optional<BsdfSample> sample(Vec3f wo, float uc, Vec2f u,
                                     TransportMode mode = TransportMode::Radiance) const;
    /// True when the lobe is a Dirac delta: the vertex is "S" in the path's Heckbert string.
    bool isDelta() const;
    /// A representative reflectance (diffuse albedo or specular tint) for G-buffers and guides.
    Rgb albedo() const;

    const Frame& frame() const { return frame_; }
    Vec3f geometricNormal() const { return ng_; }
    const BsdfLobe& lobe() const { return lobe_; }

  private:
    Frame frame_;
    Vec3f ng_{0, 0, 1};
    BsdfLobe lobe_;
};

}  // namespace partita
