// What a ray hit: the surface point with its normals. Texture coordinates are not part of it:
// only textured materials need them, so RenderScene::textureCoordinates interpolates them on
// demand from the triangle and barycentrics recorded here.
#pragma once

#include <cstdint>

#include "math/vec.h"

namespace partita {

struct SurfaceHit {
    float t = 0;
    Vec3f p;
    Vec3f ng;  // unit geometric normal from the triangle's winding (world space)
    Vec3f ns;  // unit interpolated shading normal, flipped to ng's side
    uint32_t mesh = 0, triangle = 0;
    Vec2f barycentric;  // Embree's (u, v): p = (1-u-v) p0 + u p1 + v p2
};

}  // namespace partita
