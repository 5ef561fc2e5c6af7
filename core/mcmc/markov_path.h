// A Markov chain's state: a complete path with what the chain needs of it at every step, f(x)
// with Dirac vertices as their branch coefficients (dirac_vertex.h), f* (its luminance, the
// target of the chains, paper Eq. 3), its Heckbert type and its raster position.
#pragma once

#include <vector>

#include "math/vec.h"
#include "path/path_vertex.h"
#include "path_type.h"

namespace partita {

class Camera;
class RenderScene;

struct MarkovPath {
    std::vector<PathVertex> vertices;  // x0 (camera) .. xM (light)
    Rgb f{0.0f};
    float fStar = 0;
    PathType type;
    Vec2f raster;

    int size() const { return int(vertices.size()); }
    const PathVertex& operator[](int i) const { return vertices[size_t(i)]; }
};

/// Fills f, f*, type and raster from the vertices (visibility is the caller's: every edge must
/// have been traced or tested). False, with f* = 0, when the path carries nothing: black, not
/// finite, or seen outside the camera's importance.
bool evaluatePath(const RenderScene& scene, const Camera& camera, MarkovPath& x);

}  // namespace partita
