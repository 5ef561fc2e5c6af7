// Shared by the glTF loader's parts (internal; not included outside core/gltf/): the load
// context, error and warning reporting, and safe conversions of untrusted numbers.
#pragma once

#include <fmt/format.h>
#include <tiny_gltf.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gltf/gltf_loader.h"
#include "scene_data.h"

namespace partita::gltf {

/// What every stage reads (the parsed model, the limits) and writes (the scene, warnings).
struct LoadContext {
    const tinygltf::Model& model;
    const GltfLoadLimits& limits;
    SceneData& scene;
    uint64_t trianglesEmitted = 0;
    uint64_t elementsDecoded = 0;  // accessor elements read so far (see gltf_accessors)
    uint64_t texturePixels = 0;    // pixels of all SceneData::textures so far

    /// Logs through spdlog and records the message in SceneData::warnings.
    void warn(const std::string& message);
};

/// Throws SceneLoadError with `message` (one line).
[[noreturn]] void fail(const std::string& message);

template <typename... Args>
[[noreturn]] void failf(fmt::format_string<Args...> format, Args&&... args) {
    fail(fmt::format(format, std::forward<Args>(args)...));
}

/// `items[index]`, or a SceneLoadError naming `what` when the index is out of range.
template <typename T>
const T& checkedAt(const std::vector<T>& items, int index, const char* what) {
    if (index < 0 || size_t(index) >= items.size())
        failf("{} index {} is out of range (the file has {})", what, index, items.size());
    return items[size_t(index)];
}

/// double -> float without undefined behaviour: out-of-range values clamp to +-FLT_MAX, NaN stays.
float toFloat(double v);
/// `v` if finite and inside [lo, hi], else clamped (NaN -> `fallback`).
float clampedFloat(double v, float lo, float hi, float fallback);

// tinygltf::Value helpers. A missing key, a non-object or a wrong type yields nullopt / nullptr.
const tinygltf::Value* member(const tinygltf::Value& object, const char* key);
std::optional<double> numberMember(const tinygltf::Value& object, const char* key);
/// An integral number that fits in int.
std::optional<int> intMember(const tinygltf::Value& object, const char* key);
/// The extension object `name` in `extensions`, or nullptr when the extension is absent. An
/// extension present with an empty object is returned as a (null-typed) Value.
const tinygltf::Value* findExtension(const tinygltf::ExtensionMap& extensions, const char* name);

}  // namespace partita::gltf
