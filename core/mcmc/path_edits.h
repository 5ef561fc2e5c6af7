// Small operations the mutations share on a path's vertices: tracing one more vertex, following
// a Dirac vertex's branch, testing an edge, the density of a retraced vertex, and the density
// of a fresh camera ray (core/mcmc; no mutation owns them).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "bsdf.h"
#include "mcmc/markov_path.h"
#include "path/path_vertex.h"

namespace partita {

class Camera;
class RenderScene;

/// The vertex hit from `from` in the unit direction w: a surface, or the environment's vertex
/// when the ray leaves the scene and there is one; nullopt otherwise.
std::optional<PathVertex> traceVertex(const RenderScene& scene, const PathVertex& from, Vec3f w,
                                      uint64_t& rays);

/// Whether the Dirac vertex v links the directions a and b by refraction (they lie on opposite
/// sides of its geometric normal).
bool isRefraction(const PathVertex& v, Vec3f a, Vec3f b);

/// The direction leaving the Dirac vertex v, seen from `wo`, along its reflection or refraction
/// branch (the branch a perturbation keeps); nullopt when it has none (total internal
/// reflection). `mode` is the walk's: Radiance from the camera side, Importance from the light.
std::optional<Vec3f> followBranch(const PathVertex& v, Vec3f wo, bool refraction,
                                  TransportMode mode);

/// Retraces a chain of x's Dirac vertices with a new start: from `from` along w, through the
/// vertices x[first], x[first + step], ... while they are Dirac (keeping each one's reflection
/// or refraction branch), to the first one that is not, appending the new vertices to `out`.
/// step is +1 from the camera side (mode Radiance) or -1 from the light side (Importance). A
/// chain that ends at x's light must end at a light again (asLightVertex). Returns the index
/// where the chain ends, or -1 when the new chain does not have x's structure.
int retraceChain(const RenderScene& scene, const MarkovPath& x, const PathVertex& from, Vec3f w,
                 int first, int step, std::vector<PathVertex>& out, uint64_t& rays);

/// Whether nothing blocks the edge a -- b. Counts the shadow ray.
bool visible(const RenderScene& scene, const PathVertex& a, const PathVertex& b, uint64_t& rays);

/// A surface vertex on an area light (or the environment's) as the last vertex of a path.
PathVertex asLightVertex(const RenderScene& scene, PathVertex v);

/// Whether v is the vertex of a light at infinity (the environment, a directional light): its
/// coordinate in path space is a direction, not a point.
bool isInfiniteLightVertex(const RenderScene& scene, const PathVertex& v);

/// A kept infinite light vertex reconnected to a moved neighbour: the same direction (its path
/// space coordinate), its stand-in point re-placed beyond the scene from `neighbour`. `old` is
/// the position of its neighbour on the path it is kept from.
PathVertex reanchoredLight(const RenderScene& scene, const PathVertex& light, Vec3f old,
                           Vec3f neighbour);

/// Completes a perturbed prefix y_0 .. y_c (in `y`) with x's vertices x_{c+1} .. by a new edge
/// y_c -- x_{c+1}: connectable, unoccluded, and an infinite light re-anchored. False when the
/// edge cannot be made.
bool reconnect(const RenderScene& scene, const Camera& camera, const MarkovPath& x, int c,
               std::vector<PathVertex>& y, uint64_t& rays);

/// Whether a connection edge may join the eye-side vertex a and the light-side vertex b: a is
/// not Dirac (the camera itself only when it can be connected to), b is not Dirac unless it is
/// the path's light and a is a surface (next-event estimation reaches any light).
bool connectable(const Camera& camera, const PathVertex& a, const PathVertex& b, bool bIsLast);

/// The area density of vertex `to` reached along the direction from `from` chosen with density
/// 1 in solid angle: a perturbation's retraced vertex, the proposal's own density cancelling.
inline float retracedDensity(const PathVertex& from, const PathVertex& to) {
    return solidAngleToArea(1.0f, from, to);
}

/// The first index >= `from` whose vertex is not Dirac (x's last vertex, the light, ends the
/// search whatever it is); -1 when from is past the end.
int firstNonDirac(const MarkovPath& x, int from);

/// The density of x1 .. x_last retraced from the camera through a perturbed raster position:
/// the camera's direction density at x1 (the raster Jacobian, up to a constant), then
/// retracedDensity for each vertex after it. The lens and multi-chain perturbations' T, the
/// symmetric perturbation densities cancelling.
double retracedEyeDensity(const Camera& camera, const MarkovPath& x, int last);

/// The density of x_{a-1} .. x1 retraced from x_a along a perturbed direction: retracedDensity
/// for x_{a-1}, then for each vertex reached through a Dirac vertex x_{i+1} from the light side
/// its branch's J = dw_L / dw_E (dirac_vertex.h). The caustic perturbation's T.
double retracedLightDensity(const MarkovPath& x, int a);

/// Fresh camera rays of the mutations (and of the bootstrap) go through a raster position
/// uniform over the camera's importance support, the image widened by half a pixel on every
/// side (camera.h). Their true density is Camera::directionPdf (normalised over the image)
/// times this factor: image area over support area.
float cameraSupportScale(const Camera& camera);

/// A raster position uniform over the importance support, from u in [0, 1)^2.
Vec2f sampleSupportRaster(const Camera& camera, Vec2f u);

}  // namespace partita
