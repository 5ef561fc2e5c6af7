// A Bsdf with its outgoing direction wo fixed, for an integrator that queries one path vertex
// several times (next-event estimation evaluates f and the pdf towards the light, then the
// continuation is sampled). What depends only on wo is done once: wo in the local frame, its
// side of the geometric normal, and the mirroring that makes opaque surfaces two-sided.
//
// The results are those of Bsdf::eval, Bsdf::pdf and Bsdf::sample with the same wo, bit for bit:
// those three are implemented with this class (bsdf.cpp), so the rules described in bsdf.cpp
// (two-sided opaque lobes, no light leaks through shading normals) have one implementation,
// here. It is inline because it is on the path tracer's hot path.
#pragma once

#include <optional>

#include "bsdf.h"

namespace partita {

class BoundBsdf {
  public:
    /// `bsdf` must outlive this object. The local directions the lobe sees are mirrored (z
    /// negated, for wo and wi alike) for opaque lobes seen from the back of ng.
    BoundBsdf(const Bsdf& bsdf, Vec3f wo)
        : bsdf_(bsdf),
          woLocal_(bsdf.frame().toLocal(wo)),
          cosNgO_(dot(wo, bsdf.geometricNormal())) {
        flip_ = !isTransmissive(bsdf.lobe()) && cosNgO_ < 0;
        if (flip_) woLocal_.z = -woLocal_.z;
    }

    /// Bsdf::isDelta, inline.
    bool isDelta() const {
        return std::visit([](const auto& l) { return l.isDelta(); }, bsdf_.lobe());
    }

    /// Whether the lobe transmits (and so must tell the front of ng from its back).
    static bool isTransmissive(const BsdfLobe& lobe) {
        return std::holds_alternative<DielectricLobe>(lobe) ||
               std::holds_alternative<SmoothDielectricLobe>(lobe);
    }

    struct Value {
        Rgb f{0.0f};    // Bsdf::eval(wo, wi)
        float pdf = 0;  // Bsdf::pdf(wo, wi)
    };
    /// f and pdf for wi at once (one transform of wi, one dispatch to the lobe).
    Value evalPdf(Vec3f wi, TransportMode mode = TransportMode::Radiance) const {
        std::optional<Vec3f> w = localWi(wi);
        if (!w) return {};
        if (const auto* lambert = std::get_if<LambertLobe>(&bsdf_.lobe()))
            return {lambert->eval(woLocal_, *w, mode), lambert->pdf(woLocal_, *w)};
        return lobeEvalPdf(*w, mode);
    }
    Rgb eval(Vec3f wi, TransportMode mode = TransportMode::Radiance) const;
    float pdf(Vec3f wi) const;
    std::optional<BsdfSample> sample(float uc, Vec2f u,
                                     TransportMode mode = TransportMode::Radiance) const;
    /// The same sample written into `out`; false (out unspecified) when there is none. The form
    /// for hot loops: no std::optional<BsdfSample> is returned.
    bool sample(float uc, Vec2f u, BsdfSample& out,
                TransportMode mode = TransportMode::Radiance) const {
        if (woLocal_.z == 0) return false;
        const auto* lambert = std::get_if<LambertLobe>(&bsdf_.lobe());
        std::optional<BsdfSample> s =
            lambert ? lambert->sample(woLocal_, uc, u, mode) : lobeSample(uc, u, mode);
        if (!s || s->pdf <= 0) return false;
        Vec3f wiShading = s->wi;  // in the (unmirrored) shading frame
        if (flip_) wiShading.z = -wiShading.z;
        Vec3f wi = bsdf_.frame().toWorld(wiShading);
        if (!consistentSides(woLocal_, s->wi, cosNgO_, dot(wi, bsdf_.geometricNormal())))
            return false;
        // Field by field rather than `out = *s`: a block copy of the lobe's freshly written
        // fields stalls on store forwarding (it was 2% of the path tracer's time).
        out.f = s->f;
        out.wi = wi;
        out.pdf = s->pdf;
        out.isDelta = s->isDelta;
        out.isTransmission = s->isTransmission;
        out.eta = s->eta;
        return true;
    }

  private:
    // Lambert, by far the most common lobe in the shipped scenes, is dispatched inline above; the
    // other lobes go through std::visit in bsdf.cpp.
    Value lobeEvalPdf(Vec3f wiLocal, TransportMode mode) const;
    std::optional<BsdfSample> lobeSample(float uc, Vec2f u, TransportMode mode) const;

    /// The lobe may give a non-zero value for (wo, wi) only if the lobe's notion of reflection
    /// (same side of the shading normal) agrees with the geometric one (same side of ng).
    static bool consistentSides(Vec3f woLocal, Vec3f wiLocal, float cosNgO, float cosNgI) {
        if (cosNgO == 0 || cosNgI == 0) return false;
        bool geometricReflection = (cosNgO > 0) == (cosNgI > 0);
        bool shadingReflection = woLocal.z * wiLocal.z > 0;
        return geometricReflection == shadingReflection;
    }

    /// wi in the lobe's frame (mirrored with wo), or nothing when the pair must be zero.
    std::optional<Vec3f> localWi(Vec3f wi) const {
        Vec3f w = bsdf_.frame().toLocal(wi);
        if (flip_) w.z = -w.z;
        if (!consistentSides(woLocal_, w, cosNgO_, dot(wi, bsdf_.geometricNormal())))
            return std::nullopt;
        return w;
    }

    const Bsdf& bsdf_;
    Vec3f woLocal_;  // wo in the shading frame, z mirrored when flip_
    float cosNgO_;   // dot(wo, ng)
    bool flip_;      // opaque lobe seen from the back of ng: the local z axis is mirrored
};

}  // namespace partita
