// Camera and light subpaths (Veach 1997, ch. 10): random walks that record every vertex with its
// throughput and its densities in area measure (path_vertex.h), for BDPT's connections and the
// MCMC methods' bidirectional mutation.
//
// Shading normals make light transport non-reciprocal. Paths are measured as the path tracer
// measures them (radiance transport): each edge x_i -- x_{i+1} carries
// |cos_s(x_i)| |cos_g(x_{i+1})| / d^2, the shading cosine at its camera end and the geometric
// one at its light end. A camera walk's weight is then pt's f |cos_s| / pdf per vertex; a light
// walk samples BSDFs in importance mode and weighs with the geometric cosine of the sampled
// direction and |cos_s| / |cos_g| of the arriving one (Veach's adjoint with shading normals), so
// both kinds of subpath estimate the same measurement.
#pragma once

#include <cstdint>
#include <vector>

#include "bsdf.h"
#include "path/path_vertex.h"
#include "ray.h"
#include "rng.h"

namespace partita {

class Camera;
class RenderScene;

struct WalkSettings {
    int maxVertices = 18;        // of the subpath, its camera or light vertex included
    int rouletteStartDepth = 3;  // Russian roulette from this many scattering vertices on (pt's)
    /// Stop at the vertex after the first non-specular one scattered from: no later vertex can
    /// belong to a path of the direct-light class L S* E, L D S* E (mlt's per-pixel direct
    /// light, integrators/mlt/direct_light.h). The vertices before are those of a full walk.
    bool stopAfterNonSpecular = false;
};

/// The camera subpath whose first ray is `primary` (from Camera::generateRay): out[0] is the
/// camera, then one vertex per surface hit. `rays` counts the closest-hit queries.
void traceCameraSubpath(const RenderScene& scene, const Camera& camera, const Ray& primary,
                        Rng& rng, const WalkSettings& settings, std::vector<PathVertex>& out,
                        uint64_t& rays);

/// A light subpath: a light chosen by power, an emitted ray (sampleLe), then surface hits.
/// Empty when the scene has no light or the light sends nothing.
void traceLightSubpath(const RenderScene& scene, Rng& rng, const WalkSettings& settings,
                       std::vector<PathVertex>& out, uint64_t& rays);

/// Up to `count` more vertices on `path` (at least two vertices, the last a surface), sampling
/// the last vertex's BSDF given the one before it and walking on, without Russian roulette: a
/// camera-side walk for TransportMode::Radiance, a light-side one (the path stored light
/// first) for Importance. Fewer are added when the walk escapes or is absorbed; a camera walk
/// that escapes into the environment appends its vertex. The bidirectional mutation's
/// additions (its densities come from recomputeDensities, not from the walk).
void extendSubpath(const RenderScene& scene, Rng& rng, TransportMode mode, int count,
                   std::vector<PathVertex>& path, uint64_t& rays);

/// The surface vertex of `hit`, seen from the direction wo (its BSDF, Dirac flag, area light);
/// densities and throughput left unset.
PathVertex surfaceVertex(const RenderScene& scene, const SurfaceHit& hit, Vec3f wo);

/// What the light vertex v sends towards the point `towards`: radiance (area lights, the
/// environment), intensity (point, spot) or irradiance (directional), before any geometry.
Rgb emittedTowards(const RenderScene& scene, const PathVertex& v, Vec3f towards);

/// The light vertex for light `light` at point p with normal n (zero without a surface), its
/// density set; `towardsLight` is the direction from the scene towards it (the environment's
/// density depends on it).
PathVertex lightVertex(const RenderScene& scene, int light, Vec3f p, Vec3f n, const SurfaceHit& hit,
                       Vec3f towardsLight);

}  // namespace partita
