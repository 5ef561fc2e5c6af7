// A Bsdf with its outgoing direction wo fixed, for an integrator that queries one path vertex
// several times (next-event estimation evaluates f and the pdf towards the light, then the
// continuation is sampled). What depends only on wo is done once: wo in the local frame, its
// side of the geometric normal, and the mirroring that makes opaque surfaces two-sided.
//
// The results are those of Bsdf::eval, Bsdf::pdf and Bsdf::sample with the same wo, bit for bit:
// those three are implemented with this class (bsdf.cpp), so the rules of bsdf.cpp (two-sided
// opaque lobes, no light leaks through shading normals) have one implementation.
#pragma once

#include <optional>

#include "bsdf.h"

namespace partita {

class BoundBsdf {
public:
    /// `bsdf` must outlive this object. The local directions the lobe sees are mirrored (z
    /// negated, for wo and wi alike) for opaque lobes seen from the back of ng.
    BoundBsdf(const Bsdf& bsdf, Vec3f wo)
        : bsdf_(bsdf), woLocal_(bsdf.frame().toLocal(wo)), cosNgO_(dot(wo, bsdf.geometricNormal())) {
        flip_ = !isTransmissive(bsdf.lobe()) && cosNgO_ < 0;
        if (flip_) woLocal_.z = -woLocal_.z;
    }

    /// Whether the lobe transmits (and so must tell the front of ng from its back).
    static bool isTransmissive(const BsdfLobe& lobe) {
        return std::holds_alternative<DielectricLobe>(lobe) || std::holds_alternative<SmoothDielectricLobe>(lobe);
    }

    struct Value {
        Rgb f{0.0f};  // Bsdf::eval(wo, wi)
        float pdf = 0;  // Bsdf::pdf(wo, wi)
    };
    /// f and pdf for wi at once (one transform of wi, one dispatch to the lobe).
    Value evalPdf(Vec3f wi, TransportMode mode = TransportMode::Radiance) const;
    Rgb eval(Vec3f wi, TransportMode mode = TransportMode::Radiance) const;
    float pdf(Vec3f wi) const;
    std::optional<BsdfSample> sample(float uc, Vec2f u, TransportMode mode = TransportMode::Radiance) const;
    /// The same sample written into `out`; false (out unspecified) when there is none. The form
    /// for hot loops: no std::optional<BsdfSample> is copied on the way out.
    bool sample(float uc, Vec2f u, BsdfSample& out, TransportMode mode = TransportMode::Radiance) const;

private:
    /// wi in the lobe's frame (mirrored with wo), or nothing when the pair must be zero.
    std::optional<Vec3f> localWi(Vec3f wi) const;

    const Bsdf& bsdf_;
    Vec3f woLocal_;     // wo in the shading frame, z mirrored when flip_
    float cosNgO_;      // dot(wo, ng)
    bool flip_;         // opaque lobe seen from the back of ng: the local z axis is mirrored
};

}  // namespace partita
