// A complete light path x0 (camera) .. xM (light), as BDPT's connections and the MCMC methods
// hold it (DESIGN.md "Layout of the MCMC work"), and what can be computed from its vertices
// alone, whatever sampled them:
//
// - f(x), the path's contribution (paper Eq. 2) in the measurement the path tracer estimates
//   (random_walk.h): f(x) = We(x0 -> x1) prod_i Gs(x_i, x_{i+1}) prod_{0<i<M} f_s(x_i) Le(x_M),
//   with Gs(x_i, x_{i+1}) = |cos_s(x_i)| |cos_g(x_{i+1})| / |x_i - x_{i+1}|^2. The camera vertex
//   is in image-plane measure: We is the pinhole importance normalised over the image plane at
//   distance 1 (camera.h), so f is the radiance carried per unit image area, and a camera ray's
//   f / p is exactly the path tracer's weight. For a directional light the last edge is
//   |cos_s(x_{M-1})| alone and Le its irradiance. Dirac vertices have no finite f: zero, or,
//   for the MCMC methods, their branch's coefficient (dirac_vertex.h);
// - every vertex's densities (pdfFromEye, pdfFromLight) recomputed from the geometry;
// - the Heckbert type, the raster position;
// - verify(): compares the cached densities with the recomputed ones;
// - a compact serialisation (mesh, triangle, barycentrics per vertex) from which the path is
//   rebuilt exactly in the same scene (a chain's state can move between processes).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "path/mis.h"
#include "path/path_vertex.h"
#include "path_type.h"

namespace partita {

class Camera;
class RenderScene;

/// How Dirac vertices enter f and the densities. `Zero`: f is 0 and the densities they generate
/// are 0, MIS's convention (mis.h). `Coefficient`: f holds each branch's coefficient and the
/// densities its probability (and J from the light side), so that f / p is the strategy's
/// weight and ratios f(y) / T(x->y) of the MCMC methods are exact (dirac_vertex.h).
enum class DiracVertices { Zero, Coefficient };

/// f(x) of the path (see above); zero when the camera is orthographic (a delta in direction),
/// when a Dirac vertex has no branch linking its neighbours, and, with `Zero`, at any Dirac
/// vertex. Visibility is not tested.
Rgb pathContribution(const RenderScene& scene, const Camera& camera,
                     std::span<const PathVertex> path, DiracVertices dirac = DiracVertices::Zero);

/// Scalar contribution f*(x): the luminance of f(x).
float pathLuminance(const RenderScene& scene, const Camera& camera,
                    std::span<const PathVertex> path, DiracVertices dirac = DiracVertices::Zero);

/// The densities of every vertex from its neighbours, from positions, normals and BSDFs alone.
/// fromEye(x0) is 1 (the pinhole) and fromLight(x0) 0 (nothing samples the camera); at a
/// Dirac vertex the densities it would generate follow `dirac` (see above).
std::vector<VertexDensities> recomputeDensities(const RenderScene& scene, const Camera& camera,
                                                std::span<const PathVertex> path,
                                                DiracVertices dirac = DiracVertices::Zero);

/// The Heckbert type of the path's scattering vertices x1 .. x_{M-1}.
PathType pathType(std::span<const PathVertex> path);

/// Raster position of x1 seen from the camera, or nullopt when it is behind it.
std::optional<Vec2f> pathRaster(const Camera& camera, std::span<const PathVertex> path);

/// Empty when every cached density of the path matches the recomputed one (relative
/// tolerance), else one line naming the first vertex that does not.
std::string verifyPath(const RenderScene& scene, const Camera& camera,
                       std::span<const PathVertex> path, float tolerance = 1e-3f);

/// Compact form of the path's vertices: per vertex its kind, light, mesh, triangle and
/// barycentrics (or position for the camera and punctual lights): 32 bytes a vertex.
std::vector<uint8_t> serializePath(std::span<const PathVertex> path);
/// The path rebuilt in `scene` (BSDFs, normals, densities recomputed; beta left 1). Throws
/// std::invalid_argument for bytes that are not a path of this scene.
std::vector<PathVertex> deserializePath(const RenderScene& scene, const Camera& camera,
                                        std::span<const uint8_t> bytes);

}  // namespace partita
