// The glTF node hierarchy: local transforms (matrix or TRS) and the flattening of the default
// scene into nodes with world transforms. The hierarchy must be a set of strict trees: a cycle,
// a node reached twice, or a path deeper than GltfLoadLimits::maxNodeDepth is an error.
#pragma once

#include <tiny_gltf.h>

#include <vector>

#include "math/transform.h"

namespace partita::gltf {

struct LoadContext;

struct NodeInstance {
    int node = -1;
    Mat4 toWorld;
};

/// Node `index`'s transform relative to its parent. Non-finite numbers or arrays of the wrong
/// length are errors; a zero quaternion is treated as no rotation (with a warning).
Mat4 localTransform(LoadContext& ctx, const tinygltf::Node& node, int index);

/// The nodes of the default scene (`scene`, else scene 0; all its root nodes), depth-first, each
/// with its world transform. A file without scenes uses every node that has no parent.
std::vector<NodeInstance> flattenDefaultScene(LoadContext& ctx);

}  // namespace partita::gltf
