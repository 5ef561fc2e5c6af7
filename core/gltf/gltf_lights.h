// KHR_lights_punctual. tinygltf 2.7 parses the file's light list into Model::lights but leaves the
// node-to-light link in node.extensions["KHR_lights_punctual"]["light"].
#pragma once

#include <tiny_gltf.h>

#include <optional>

#include "math/transform.h"
#include "scene_data.h"

namespace partita::gltf {

struct LoadContext;

/// The light attached to `node`, in world space (position = node origin, direction = node -Z),
/// or nullopt when the node has none or (with a warning) it cannot be placed.
std::optional<PunctualLightDesc> convertNodeLight(LoadContext& ctx, const tinygltf::Node& node,
                                                  int nodeIndex, const Mat4& toWorld);

}  // namespace partita::gltf
