// Bsdf and BoundBsdf (a Bsdf with wo fixed, which implements Bsdf's queries): world <-> local
// conversion around the lobes, two-sided opaque surfaces, and the guard against light leaks
// through shading normals.
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

namespace {

// The lobe may give a non-zero value for (wo, wi) only if the lobe's notion of reflection
// (same side of the shading normal) agrees with the geometric one (same side of ng).
bool consistentSides(Vec3f woLocal, Vec3f wiLocal, float cosNgO, float cosNgI) {
    if (cosNgO == 0 || cosNgI == 0) return false;
    bool geometricReflection = (cosNgO > 0) == (cosNgI > 0);
    bool shadingReflection = woLocal.z * wiLocal.z > 0;
    return geometricReflection == shadingReflection;
}

}  // namespace

std::optional<Vec3f> BoundBsdf::localWi(Vec3f wi) const {
    Vec3f w = bsdf_.frame().toLocal(wi);
    if (flip_) w.z = -w.z;
    if (!consistentSides(woLocal_, w, cosNgO_, dot(wi, bsdf_.geometricNormal()))) return std::nullopt;
    return w;
}

BoundBsdf::Value BoundBsdf::evalPdf(Vec3f wi, TransportMode mode) const {
    std::optional<Vec3f> w = localWi(wi);
    if (!w) return {};
    return std::visit([&](const auto& l) { return Value{l.eval(woLocal_, *w, mode), l.pdf(woLocal_, *w)}; },
                      bsdf_.lobe());
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

bool BoundBsdf::sample(float uc, Vec2f u, BsdfSample& out, TransportMode mode) const {
    if (woLocal_.z == 0) return false;
    std::optional<BsdfSample> s =
        std::visit([&](const auto& l) { return l.sample(woLocal_, uc, u, mode); }, bsdf_.lobe());
    if (!s || s->pdf <= 0) return false;
    Vec3f wiShading = s->wi;  // in the (unmirrored) shading frame
    if (flip_) wiShading.z = -wiShading.z;
    Vec3f wi = bsdf_.frame().toWorld(wiShading);
    if (!consistentSides(woLocal_, s->wi, cosNgO_, dot(wi, bsdf_.geometricNormal()))) return false;
    // Field by field rather than `out = *s`: a block copy of the lobe's freshly written fields
    // stalls on store forwarding (it was 2% of the path tracer's time).
    out.f = s->f;
    out.wi = wi;
    out.pdf = s->pdf;
    out.isDelta = s->isDelta;
    out.isTransmission = s->isTransmission;
    out.eta = s->eta;
    return true;
}

std::optional<BsdfSample> BoundBsdf::sample(float uc, Vec2f u, TransportMode mode) const {
    BsdfSample s;
    if (!sample(uc, u, s, mode)) return std::nullopt;
    return s;
}

Rgb Bsdf::eval(Vec3f wo, Vec3f wi, TransportMode mode) const { return BoundBsdf(*this, wo).eval(wi, mode); }

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
