#include "path/transmittance.h"

#include "medium.h"
#include "render_scene.h"

namespace partita {

namespace {

/// The absorption coefficient of the medium the segment from v towards `to` runs through, as
/// far as v's own surface tells.
Rgb absorptionBehind(const RenderScene& scene, const PathVertex& v, Vec3f to) {
    if (!v.isSurface() || dot(to - v.p, v.ng) >= 0) return Rgb(0.0f);
    return absorptionOf(scene.materialOf(v.hit));
}

}  // namespace

Rgb edgeTransmittance(const RenderScene& scene, const PathVertex& a, const PathVertex& b) {
    if (!scene.hasAbsorption()) return Rgb(1.0f);
    Rgb sigma = absorptionBehind(scene, a, b.p);
    if (isBlack(sigma)) sigma = absorptionBehind(scene, b, a.p);
    return beerLambert(sigma, length(b.p - a.p));
}

}  // namespace partita
