#include "gltf/gltf_common.h"

#include <spdlog/spdlog.h>

#include <cfloat>
#include <cmath>

namespace partita::gltf {

void LoadContext::warn(const std::string& message) {
    spdlog::warn("glTF: {}", message);
    scene.warnings.push_back(message);
}

void fail(const std::string& message) { throw SceneLoadError(message); }

float toFloat(double v) {
    if (std::isnan(v)) return NAN;
    if (v > double(FLT_MAX)) return v == INFINITY ? INFINITY : FLT_MAX;
    if (v < -double(FLT_MAX)) return v == -INFINITY ? -INFINITY : -FLT_MAX;
    return float(v);
}

float clampedFloat(double v, float lo, float hi, float fallback) {
    if (std::isnan(v)) return fallback;
    return clamp(toFloat(v), lo, hi);
}

const tinygltf::Value* member(const tinygltf::Value& object, const char* key) {
    if (!object.IsObject() || !object.Has(key)) return nullptr;
    return &object.Get(key);
}

std::optional<double> numberMember(const tinygltf::Value& object, const char* key) {
    const tinygltf::Value* v = member(object, key);
    if (!v || !v->IsNumber()) return std::nullopt;
    return v->GetNumberAsDouble();
}

std::optional<int> intMember(const tinygltf::Value& object, const char* key) {
    std::optional<double> d = numberMember(object, key);
    // tinygltf's own GetNumberAsInt() casts doubles unchecked; range-check before converting.
    if (!d || !(*d >= double(INT32_MIN) && *d <= double(INT32_MAX)) || std::floor(*d) != *d)
        return std::nullopt;
    return int(*d);
}

const tinygltf::Value* findExtension(const tinygltf::ExtensionMap& extensions, const char* name) {
    auto it = extensions.find(name);
    return it == extensions.end() ? nullptr : &it->second;
}

}  // namespace partita::gltf
