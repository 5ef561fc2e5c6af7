// glTF mesh primitives to triangles: decoding (object space, once per mesh) and instancing (world
// space, once per node that uses the mesh).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "math/transform.h"
#include "scene_data.h"

namespace partita::gltf {

struct LoadContext;

/// One triangle primitive in object space.
struct PrimitiveGeometry {
    std::string name;
    std::vector<Vec3f> positions;
    std::vector<Vec3f> normals;  // empty when the file has none
    std::array<std::vector<Vec2f>, 2> uvs;
    std::vector<uint32_t> indices;  // 3 per triangle, all < positions.size()
    int material = -1;
};

/// The triangle primitives of mesh `meshIndex`. Modes 4/5/6 (triangles, strips, fans) become
/// triangle lists; points and lines are skipped with a warning; a degenerate triangle (a repeated
/// index, as strips use to restart) is dropped.
std::vector<PrimitiveGeometry> decodeMesh(LoadContext& ctx, int meshIndex);

/// `geometry` placed by `toWorld` (whose 3x3 must be invertible). Normals go through the inverse
/// transpose; a negative determinant flips the winding so that the front face stays in front;
/// without file normals, vertices are un-welded and get their face's flat normal.
TriangleMesh instantiate(const PrimitiveGeometry& geometry, const Mat4& toWorld);

/// glTF's triangle list for `mode` (4, 5 or 6) over vertex references `v`.
std::vector<uint32_t> assembleTriangles(int mode, const std::vector<uint32_t>& v);

}  // namespace partita::gltf
