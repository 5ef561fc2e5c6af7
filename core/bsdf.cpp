// Bsdf's queries: world <-> local conversion around the lobes, two-sided opaque surfaces, and
// the guard against light leaks through shading normals. They are implemented by BoundBsdf (a
// Bsdf with wo fixed, bsdfs/bound_bsdf.h, inline there for the path tracer's hot path); this
// file has the lobe dispatch for it and the rules it follows.
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

#include "bsdfs/bound_bsdf.h"

namespace partita {

BoundBsdf::Value BoundBsdf::lobeEvalPdf(Vec3f w, TransportMode mode) const {
    return std::visit(
        [&](const auto& l) {
            return Value{l.eval(woLocal_, w, mode), l.pdf(woLocal_, w)};
        },
        bsdf_.lobe());
}

std::optional<BsdfSample> BoundBsdf::lobeSample(float uc, Vec2f u, TransportMode mode) const {
    return std::visit([&](const auto& l) { return l.sample(woLocal_, uc, u, mode); }, bsdf_.lobe());
}

Rgb BoundBsdf::eval(Vec3f wi, TransportMode mode) const {
    std::optional<Vec3f> w = localWi(wi);
    if (!w) return Rgb(0.0f);
    return std::visit([&](const auto& l) { return l.eval(woLocal_, *w, mode); }, bsdf_.lobe());
}

float BoundBsdf::pdf(Vec3f wi) const {
    std::optional<Vec3f> w = localWi(wi);
    if (!w) return 0;
    return std::visit([&](const auto& l) { return l.pdf(woLocal_, *w); }, bsdf_.lobe());
}

std::optional<BsdfSample> BoundBsdf::sample(float uc, Vec2f u, TransportMode mode) const {
    BsdfSample s;
    if (!sample(uc, u, s, mode)) return std::nullopt;
    return s;
}

Rgb Bsdf::eval(Vec3f wo, Vec3f wi, TransportMode mode) const {
    return BoundBsdf(*this, wo).eval(wi, mode);
}

float Bsdf::pdf(Vec3f wo, Vec3f wi) const { return BoundBsdf(*this, wo).pdf(wi); }

std::optional<BsdfSample> Bsdf::sample(Vec3f wo, float uc, Vec2f u, TransportMode mode) const {
    return BoundBsdf(*this, wo).sample(uc, u, mode);
}

bool Bsdf::isDelta() const {
    return std::visit([](const auto& l) { return l.isDelta(); }, lobe_);
}

Rgb Bsdf::albedo() const {
    return std::visit([](const auto& l) { return l.albedo(); }, lobe_);
}

}  // namespace partita
