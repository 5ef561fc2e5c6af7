// Checks made on the raw bytes before tinygltf sees them, for the cases where tinygltf 2.7 itself
// would read out of bounds, recurse without limit, or give a misleading message.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

namespace partita::gltf {

struct GlbLayout {
    uint32_t length = 0;  // total GLB length from the header (<= the bytes we were given)
    std::string_view json;
};

/// Validates the GLB header and chunk table (magic, version 2, lengths inside the data, BIN chunk
/// inside the declared length: tinygltf's own check lets the BIN chunk run 8 bytes past the end).
GlbLayout validateGlb(const std::vector<uint8_t>& bytes);

/// Fails when JSON arrays/objects nest deeper than `maxDepth`: tinygltf converts `extras` and
/// `extensions` to its Value type recursively, so "[[[[...]]]]" would overflow the stack.
void checkJsonNesting(std::string_view json, int maxDepth);

/// Parses the JSON once on our side for what must be refused before tinygltf runs: invalid JSON
/// (one clear line), a non-object root, a glTF major version other than 2, and required
/// extensions we cannot honour (tinygltf would fail on, e.g., Draco's accessors first and name
/// the wrong problem).
void checkGltfJson(std::string_view json);

}  // namespace partita::gltf
