// The cache key of a reference render: a hash of the scene's bytes (the .gltf/.glb file and
// every external resource it names), the algorithm and every setting that changes the image.
// Settings that do not change the image (threads: the renderers are thread-count independent;
// the preview interval) are left out, so they reuse a cached reference.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "render_settings.h"

namespace partita::eval {

/// Bumped whenever the way a reference is made changes (the half split, the seeds of the
/// halves), which invalidates every cached reference.
inline constexpr int kReferenceFormat = 2;  // 2: every declared parameter by its name

/// The seed of half `half` (0 or 1) of a reference asked for with `seed`. Far from the small
/// seeds that measured renders use (partita-eval quality: 1, 2, ...), so that no reference half
/// shares its random numbers with a render it is compared with: shared samples would correlate
/// their errors and make the measured RMSE look smaller than it is.
inline uint64_t referenceHalfSeed(uint64_t seed, int half) {
    return (uint64_t(1) << 40) + 2 * seed + uint64_t(half);
}

/// One file of a scene: "scene" for the .gltf/.glb itself (so a renamed copy keeps its key),
/// else the uri as written in the file. `hash` is 32 hex digits, "missing" for a resource that
/// cannot be read (the loader will then say why).
struct SceneFile {
    std::string name;
    uint64_t size = 0;
    std::string hash;
};

/// The scene file and the external resources its buffers and images name (not data: URIs),
/// read from its folder through the loader's FolderResolver, in the file's order, each once.
/// std::runtime_error when the scene file itself cannot be read.
std::vector<SceneFile> sceneFiles(const std::filesystem::path& scene);

/// The text the key hashes: one "name=value" line per setting and one line per file. Stored in
/// the reference's metadata, so that a key can be explained.
std::string referenceKeyText(const std::vector<SceneFile>& files, const std::string& algorithm,
                             const RenderSettings& settings);

/// 32 hex digits (128-bit FNV-1a) of `referenceKeyText`.
std::string referenceKey(const std::vector<SceneFile>& files, const std::string& algorithm,
                         const RenderSettings& settings);

/// 128-bit FNV-1a of `bytes` as 32 hex digits. Not cryptographic: it tells apart scenes and
/// settings, it does not defend a cache against someone crafting collisions.
std::string hashBytes(const void* bytes, size_t size);

}  // namespace partita::eval
