// Bsdf: world <-> local conversion around the lobes, two-sided opaque surfaces, and the guard
// against light leaks through shading normals.
//
// Two-sidedness. The frame and ng face the surface's front (see SurfacePoint in
// material_mapping.h). Transmissive lobes need that orientation to tell inside from outside.
// Opaque lobes reflect on both sides: when wo arrives from the back of ng, the frame is mirrored
// (local z negated for wo and wi) before the lobe sees the directions.
//
// Light leaks. The shading normal decides reflection vs transmission inside the lobe, but the
// geometric normal decides which side of the surface a direction really is on. A pair of
// directions on the same side of ng that the lobe treats as transmission (or on opposite sides
// that it treats as reflection) would let light through an opaque wall or reflect it off the
// inside of glass, so eval, pdf and sample all give zero for it. Doing it in all three keeps
// sample() consistent with eval()/pdf(), which MIS and MCMC acceptance ratios rely on.
#include "bsdf.h"

namespace partita {

namespace {

bool isTransmissive(const BsdfLobe& lobe) {
    return std::holds_alternative<DielectricLobe>(lobe) ||
           std::holds_alternative<SmoothDielectricLobe>(lobe);
}

// The lobe may give a non-zero value for (wo, wi) only if the lobe's notion of reflection
// (same side of the shading normal) agrees with the geometric one (same side of ng).
bool consistentSides(Vec3f woLocal, Vec3f wiLocal, float cosNgO, float cosNgI) {
    if (cosNgO == 0 || cosNgI == 0) return false;
    bool geometricReflection = (cosNgO > 0) == (cosNgI > 0);
    bool shadingReflection = woLocal.z * wiLocal.z > 0;
    return geometricReflection == shadingReflection;
}

// The local-frame directions the lobe sees: mirrored for opaque lobes hit from the back.
struct LocalPair {
    Vec3f wo, wi;
};

LocalPair toLocal(const Frame& frame, Vec3f ng, const BsdfLobe& lobe, Vec3f wo, Vec3f wi) {
    LocalPair p{frame.toLocal(wo), frame.toLocal(wi)};
    if (!isTransmissive(lobe) && dot(wo, ng) < 0) {
        p.wo.z = -p.wo.z;
        p.wi.z = -p.wi.z;
    }
    return p;
}

}  // namespace

Rgb Bsdf::eval(Vec3f wo, Vec3f wi, TransportMode mode) const {
    LocalPair p = toLocal(frame_, ng_, lobe_, wo, wi);
    if (!consistentSides(p.wo, p.wi, dot(wo, ng_), dot(wi, ng_))) return Rgb(0.0f);
    return std::visit([&](const auto& l) { return l.eval(p.wo, p.wi, mode); }, lobe_);
}

float Bsdf::pdf(Vec3f wo, Vec3f wi) const {
    LocalPair p = toLocal(frame_, ng_, lobe_, wo, wi);
    if (!consistentSides(p.wo, p.wi, dot(wo, ng_), dot(wi, ng_))) return 0;
    return std::visit([&](const auto& l) { return l.pdf(p.wo, p.wi); }, lobe_);
}

std::optional<BsdfSample> Bsdf::sample(Vec3f wo, float uc, Vec2f u, TransportMode mode) const {
    Vec3f woLocal = frame_.toLocal(wo);
    bool flip = !isTransmissive(lobe_) && dot(wo, ng_) < 0;
    if (flip) woLocal.z = -woLocal.z;
    if (woLocal.z == 0) return std::nullopt;
    std::optional<BsdfSample> s =
        std::visit([&](const auto& l) { return l.sample(woLocal, uc, u, mode); }, lobe_);
    if (!s || s->pdf <= 0) return std::nullopt;
    Vec3f wiLocal = s->wi;
    if (flip) s->wi.z = -s->wi.z;
    s->wi = frame_.toWorld(s->wi);
    if (!consistentSides(woLocal, wiLocal, dot(wo, ng_), dot(s->wi, ng_))) return std::nullopt;
    return s;
}

bool Bsdf::isDelta() const {
    return std::visit([](const auto& l) { return l.isDelta(); }, lobe_);
}

Rgb Bsdf::albedo() const {
    return std::visit([](const auto& l) { return l.albedo(); }, lobe_);
}

}  // namespace partita
