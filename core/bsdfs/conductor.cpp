#include "bsdfs/conductor.h"

#include "bsdfs/fresnel.h"

namespace partita {

namespace {
// f = D(wm) G(wo, wi) F(wo.wm) / (4 cos(wo) cos(wi)) with wm the half vector; the caller has
// checked that both directions are above the surface.
Rgb conductorValue(const TrowbridgeReitz& distrib, Rgb f0, Vec3f wo, Vec3f wi, Vec3f wm) {
    Rgb fresnel = fresnelSchlick(dot(wo, wm), f0);
    return fresnel * (distrib.D(wm) * distrib.G(wo, wi) / (4 * wo.z * wi.z));
}

// Reflection maps wm to wi with Jacobian d(wi)/d(wm) = 4 |wo.wm|.
float conductorPdf(const TrowbridgeReitz& distrib, Vec3f wo, Vec3f wm) {
    return distrib.visibleNormalPdf(wo, wm) / (4 * absDot(wo, wm));
}
}  // namespace

Rgb ConductorLobe::eval(Vec3f wo, Vec3f wi, TransportMode) const {
    if (wo.z <= 0 || wi.z <= 0) return Rgb(0.0f);
    Vec3f h = wo + wi;
    if (lengthSquared(h) == 0) return Rgb(0.0f);
    return conductorValue(TrowbridgeReitz(alpha), f0, wo, wi, normalize(h));
}

float ConductorLobe::pdf(Vec3f wo, Vec3f wi) const {
    if (wo.z <= 0 || wi.z <= 0) return 0;
    Vec3f h = wo + wi;
    if (lengthSquared(h) == 0) return 0;
    return conductorPdf(TrowbridgeReitz(alpha), wo, normalize(h));
}

std::optional<BsdfSample> ConductorLobe::sample(Vec3f wo, float, Vec2f u, TransportMode) const {
    if (wo.z <= 0) return std::nullopt;
    TrowbridgeReitz distrib(alpha);
    Vec3f wm = distrib.sampleVisibleNormal(wo, u);
    Vec3f wi = reflect(wo, wm);
    // Visible normals can still reflect wo below the horizon (masking); those samples are lost,
    // which is what pdf() integrating to less than one over the hemisphere accounts for.
    if (wi.z <= 0) return std::nullopt;
    float pdf = conductorPdf(distrib, wo, wm);
    if (pdf <= 0) return std::nullopt;
    BsdfSample s;
    s.f = conductorValue(distrib, f0, wo, wi, wm);
    s.wi = wi;
    s.pdf = pdf;
    return s;
}

Rgb DiffuseConductorMixLobe::eval(Vec3f wo, Vec3f wi, TransportMode mode) const {
    return diffuse.eval(wo, wi, mode) * (1 - metallic) + conductor.eval(wo, wi, mode) * metallic;
}

float DiffuseConductorMixLobe::pdf(Vec3f wo, Vec3f wi) const {
    return (1 - metallic) * diffuse.pdf(wo, wi) + metallic * conductor.pdf(wo, wi);
}

std::optional<BsdfSample> DiffuseConductorMixLobe::sample(Vec3f wo, float uc, Vec2f u,
                                                          TransportMode mode) const {
    if (wo.z <= 0) return std::nullopt;
    // Choose a lobe with probability equal to its weight; both lobes ignore uc, so it needs no
    // remapping. The returned f and pdf are the whole mixture's (the one-sample MIS form), so
    // f cos / pdf never has the spikes of a single lobe's weight.
    std::optional<BsdfSample> s =
        uc < metallic ? conductor.sample(wo, uc, u, mode) : diffuse.sample(wo, uc, u, mode);
    if (!s) return std::nullopt;
    s->f = eval(wo, s->wi, mode);
    s->pdf = pdf(wo, s->wi);
    if (s->pdf <= 0) return std::nullopt;
    return s;
}

}  // namespace partita
