// Absorption along a path edge (KHR_materials_volume, medium.h). An edge lies inside an absorbing
// mesh when it leaves one of its end vertices on the back side of that vertex's surface and the
// surface's material has a volume: the medium is the one behind the surface it touches. For a
// closed absorbing object with nothing inside it (the glTF extension's case) this is exactly the
// path tracer's rule (the medium entered at the last refraction).
#pragma once

#include "math/vec.h"
#include "path/path_vertex.h"

namespace partita {

class RenderScene;

/// exp(-sigma_a d) of the segment between a and b; 1 outside any absorbing medium.
Rgb edgeTransmittance(const RenderScene& scene, const PathVertex& a, const PathVertex& b);

}  // namespace partita
