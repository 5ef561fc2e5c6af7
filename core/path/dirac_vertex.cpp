#include "path/dirac_vertex.h"

#include <cmath>

#include "bsdfs/bound_bsdf.h"

namespace partita {

namespace {

/// The Dirac sample of `bsdf` seen from wo whose branch is a transmission or not: the lobes
/// pick reflection for small uc and refraction for large uc (smooth_dielectric.h).
bool sampleBranch(const Bsdf& bsdf, Vec3f wo, bool transmission, TransportMode mode,
                  BsdfSample& out) {
    BoundBsdf bound(bsdf, wo);
    for (float uc : {0.0f, 0x1.fffffep-1f}) {
        if (bound.sample(uc, Vec2f{0.5f, 0.5f}, out, mode) && out.isDelta &&
            out.isTransmission == transmission)
            return true;
    }
    return false;
}

}  // namespace

DiracBranch diracBranch(const PathVertex& v, Vec3f toEye, Vec3f toLight) {
    DiracBranch b;
    if (!v.isSurface() || !v.delta) return b;
    bool transmission = (dot(toEye, v.ng) > 0) != (dot(toLight, v.ng) > 0);
    BsdfSample eyeSide, lightSide;
    if (!sampleBranch(v.bsdf, toEye, transmission, TransportMode::Radiance, eyeSide) ||
        !sampleBranch(v.bsdf, toLight, transmission, TransportMode::Importance, lightSide))
        return b;
    b.valid = true;
    b.f = eyeSide.f;
    b.probabilityEye = eyeSide.pdf;
    b.probabilityLight = lightSide.pdf;
    if (transmission) {
        // eyeSide.eta = eta_L / eta_E (the index on the far side over the near one).
        Vec3f ns = v.hit.ns;
        float cosE = absDot(toEye, ns), cosL = absDot(toLight, ns);
        b.jacobian = cosL > 0 ? cosE / (sqr(eyeSide.eta) * cosL) : 0;
    }
    return b;
}

}  // namespace partita
