// glTF cameras (perspective, orthographic) placed by their node's world transform.
#pragma once

#include <tiny_gltf.h>

#include <optional>

#include "math/transform.h"
#include "scene_data.h"

namespace partita::gltf {

struct LoadContext;

/// The camera of `node` (index `nodeIndex`), or nullopt (with a warning) when its transform is
/// degenerate. glTF forbids scale on camera nodes; any scale or shear is removed by
/// orthonormalising the rotation (keeping the viewing direction exact).
std::optional<CameraDesc> convertCamera(LoadContext& ctx, const tinygltf::Node& node, int nodeIndex,
                                        const Mat4& toWorld);

/// The rigid part of `m`: its -Z (view) axis kept, +Y made orthogonal to it, X = Y x Z.
/// nullopt when `m` has no usable rotation.
std::optional<Mat4> orthonormalized(const Mat4& m);

}  // namespace partita::gltf
