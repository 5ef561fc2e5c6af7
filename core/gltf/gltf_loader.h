// glTF 2.0 loading through tinygltf: .gltf (JSON + external or data: resources) and .glb.
// Produces a SceneData in world space. Every malformed input is a SceneLoadError with one clear
// line, never a crash, hang or undefined behaviour.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "gltf/resource_resolver.h"
#include "scene_data.h"

namespace partita {

struct SceneLoadError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct GltfLoadLimits {
    uint64_t maxFileBytes = uint64_t(1) << 30;  // the .gltf/.glb itself and each resource
    uint64_t maxTriangles = 50'000'000;
    uint64_t maxTexturePixels = uint64_t(1) << 26;  // per texture (8192 x 8192)
    int maxNodeDepth = 256;                         // guards against deep or cyclic hierarchies
    // All textures together (each Texture counts; 4 bytes per pixel for 8-bit images, 16 for
    // 16-bit ones, which are kept as float): many small, highly compressible PNGs must not add
    // up to an unbounded amount of memory.
    uint64_t maxTotalTexturePixels = uint64_t(1) << 28;
};

/// Load a .gltf or .glb file. Resources are read only from the file's own folder.
SceneData loadGltfFile(const std::filesystem::path& file, const GltfLoadLimits& limits = {});

/// Load from bytes (`isBinary` = GLB), reading external resources through `resolver` only.
SceneData loadGltfMemory(const std::vector<uint8_t>& bytes, bool isBinary,
                         const ResourceResolver& resolver, const GltfLoadLimits& limits = {});

}  // namespace partita
