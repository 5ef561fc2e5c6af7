// The renderer-independent description of a loaded scene: world-space triangle meshes,
// materials, textures, cameras and punctual lights. Loaders produce it; RenderScene (Embree,
// lights, BSDFs) consumes it. Nothing here knows about glTF or Embree.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "environment_map.h"
#include "material.h"
#include "math/transform.h"
#include "math/vec.h"
#include "texture.h"

namespace partita {

/// Triangles in world space. `normals` always has one entry per position: the loader generates
/// flat normals (un-welding vertices) when the file has none.
struct TriangleMesh {
    std::string name;
    std::vector<Vec3f> positions;
    std::vector<Vec3f> normals;
    std::array<std::vector<Vec2f>, 2> uvs;  // TEXCOORD_0, TEXCOORD_1; each empty or per-vertex
    std::vector<uint32_t> indices;          // 3 per triangle, all < positions.size()
    int material = -1;                      // index into SceneData::materials, -1 = default

    size_t triangleCount() const { return indices.size() / 3; }
};

struct CameraDesc {
    enum class Type { Perspective, Orthographic };
    Type type = Type::Perspective;
    std::string name;
    Mat4 cameraToWorld = Mat4::identity();  // camera looks down its local -Z, +Y up (glTF)
    float yfov = 0.8f;                      // radians, perspective
    float aspectRatio = 0.0f;               // 0 = use the image's aspect
    float xmag = 1.0f, ymag = 1.0f;         // orthographic half extents
    float znear = 0.0f;
};

/// KHR_lights_punctual. Intensities are taken as radiometric, 1:1 (a candela becomes one unit of
/// radiant intensity, a lux one unit of irradiance).
struct PunctualLightDesc {
    enum class Type { Point, Spot, Directional };
    Type type = Type::Point;
    std::string name;
    Rgb color{1.0f};
    float intensity = 1.0f;
    float range = 0.0f;  // 0 = infinite; ignored (physically based falloff only)
    float innerConeAngle = 0.0f, outerConeAngle = kPi / 4;
    Vec3f position{0, 0, 0};    // world space
    Vec3f direction{0, 0, -1};  // world space, the direction light travels (node's -Z)
};

struct Bounds3f {
    Vec3f lo{kInf}, hi{-kInf};
    void expand(Vec3f p) {
        lo = min(lo, p);
        hi = max(hi, p);
    }
    bool empty() const { return lo.x > hi.x; }
    Vec3f center() const { return (lo + hi) * 0.5f; }
    Vec3f diagonal() const { return hi - lo; }
};

struct SceneData {
    std::vector<TriangleMesh> meshes;
    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<CameraDesc> cameras;
    std::vector<PunctualLightDesc> lights;
    /// Radiance from infinitely far away (not part of glTF: set by the job), or null.
    std::shared_ptr<const EnvironmentMap> environment;
    std::vector<std::string> warnings;  // things skipped or approximated while loading

    Bounds3f bounds() const;
};

}  // namespace partita
