#include "bsdfs/dielectric.h"

#include "bsdfs/fresnel.h"

namespace partita {

namespace {

// Everything eval, pdf and sample share, for a pair (wo, wi) and its (generalised) half vector.
struct Interaction {
    Vec3f wm;        // microfacet normal, wm.z > 0
    float etap = 1;  // n(wi side) / n(wo side); 1 for reflection
    bool reflection = true;
};

// The microfacet normal that maps wo to wi: the half vector for reflection, the generalised
// half vector wo + etap wi for refraction (Walter et al. eq. 16). Fails for degenerate pairs and
// for microfacets that face away from wo or wi, which cannot take part in the scattering.
std::optional<Interaction> halfVector(float eta, Vec3f wo, Vec3f wi) {
    if (wo.z == 0 || wi.z == 0) return std::nullopt;
    Interaction it;
    it.reflection = wo.z * wi.z > 0;
    if (!it.reflection) it.etap = wo.z > 0 ? eta : 1 / eta;
    Vec3f wm = wo + wi * it.etap;
    if (lengthSquared(wm) == 0) return std::nullopt;
    wm = normalize(wm);
    if (wm.z < 0) wm = -wm;
    if (wm.z == 0) return std::nullopt;
    if (dot(wm, wi) * wi.z <= 0 || dot(wm, wo) * wo.z <= 0) return std::nullopt;
    it.wm = wm;
    return it;
}

struct ValueAndPdf {
    Rgb f;
    float pdf;
};

ValueAndPdf evaluate(const DielectricLobe& lobe, const TrowbridgeReitz& distrib, Vec3f wo, Vec3f wi,
                     const Interaction& it, TransportMode mode) {
    float cosWoWm = dot(wo, it.wm), cosWiWm = dot(wi, it.wm);
    float reflectance = fresnelDielectric(cosWoWm, lobe.eta);
    float transmittance = 1 - reflectance;
    float visible = distrib.visibleNormalPdf(wo, it.wm);
    if (it.reflection) {
        float f = distrib.D(it.wm) * distrib.G(wo, wi) * reflectance / std::abs(4 * wo.z * wi.z);
        // d(wi)/d(wm) = 4 |wo.wm|; the reflection branch is chosen with probability F.
        float pdf = visible / (4 * std::abs(cosWoWm)) * reflectance;
        return {Rgb(f), pdf};
    }
    // Walter et al. eq. 21 written with etap = n_i / n_o (wi's side over wo's side):
    // f = D G (1 - F) |wi.wm| |wo.wm| / (|cos wi| |cos wo| (wi.wm + wo.wm / etap)^2) / etap^2
    // for radiance; importance omits the 1 / etap^2.
    float denom = sqr(cosWiWm + cosWoWm / it.etap);
    if (denom == 0) return {Rgb(0.0f), 0};
    float f = distrib.D(it.wm) * distrib.G(wo, wi) * transmittance *
              std::abs(cosWiWm * cosWoWm / (wi.z * wo.z * denom));
    if (mode == TransportMode::Radiance) f /= sqr(it.etap);
    // d(wm)/d(wi) = |wi.wm| / (wi.wm + wo.wm / etap)^2 (Walter et al. eq. 17); refraction is
    // chosen with probability 1 - F.
    float pdf = visible * std::abs(cosWiWm) / denom * transmittance;
    return {lobe.tint * f, pdf};
}

}  // namespace

Rgb DielectricLobe::eval(Vec3f wo, Vec3f wi, TransportMode mode) const {
    auto it = halfVector(eta, wo, wi);
    if (!it) return Rgb(0.0f);
    return evaluate(*this, TrowbridgeReitz(alpha), wo, wi, *it, mode).f;
}

float DielectricLobe::pdf(Vec3f wo, Vec3f wi) const {
    auto it = halfVector(eta, wo, wi);
    if (!it) return 0;
    return evaluate(*this, TrowbridgeReitz(alpha), wo, wi, *it, TransportMode::Radiance).pdf;
}

std::optional<BsdfSample> DielectricLobe::sample(Vec3f wo, float uc, Vec2f u,
                                                 TransportMode mode) const {
    if (wo.z == 0) return std::nullopt;
    TrowbridgeReitz distrib(alpha);
    Interaction it;
    it.wm = distrib.sampleVisibleNormal(wo, u);
    float reflectance = fresnelDielectric(dot(wo, it.wm), eta);
    Vec3f wi;
    if (uc < reflectance) {
        wi = reflect(wo, it.wm);
        if (wo.z * wi.z <= 0) return std::nullopt;  // reflected through the macro surface
    } else {
        // refract() inverts eta itself when wo is on the back of wm (inside the medium).
        if (!refract(wo, it.wm, eta, wi, it.etap)) return std::nullopt;
        if (wo.z * wi.z >= 0) return std::nullopt;  // refracted to wo's own side
        it.reflection = false;
    }
    if (wi.z == 0) return std::nullopt;
    if (dot(it.wm, wi) * wi.z <= 0 || dot(it.wm, wo) * wo.z <= 0) return std::nullopt;
    ValueAndPdf vp = evaluate(*this, distrib, wo, wi, it, mode);
    if (vp.pdf <= 0) return std::nullopt;
    BsdfSample s;
    s.f = vp.f;
    s.wi = wi;
    s.pdf = vp.pdf;
    s.isTransmission = !it.reflection;
    s.eta = it.etap;
    return s;
}

}  // namespace partita
