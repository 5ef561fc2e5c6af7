#include "gltf/gltf_extensions.h"

#include <array>
#include <string_view>

#include "gltf/gltf_common.h"

namespace partita::gltf {

namespace {

// KHR_mesh_quantization is honoured because every accessor is read with its own component type
// and `normalized` flag. KHR_materials_volume's thickness is not needed by a ray tracer that sees
// the real geometry. KHR_materials_variants only adds alternative material mappings: the
// primitives' own materials, which it leaves in place, are the default variant and are what is
// rendered (as a viewer does before a variant is picked).
constexpr std::array<std::string_view, 8> kSupported = {
    "KHR_materials_transmission",      "KHR_materials_ior",     "KHR_materials_volume",
    "KHR_materials_emissive_strength", "KHR_texture_transform", "KHR_lights_punctual",
    "KHR_mesh_quantization",           "KHR_materials_variants",
};

std::string why(const std::string& name) {
    if (name == "KHR_draco_mesh_compression" || name == "EXT_meshopt_compression")
        return " (compressed geometry cannot be decoded; export the file uncompressed)";
    if (name == "KHR_texture_basisu" || name == "EXT_texture_webp" || name == "MSFT_texture_dds")
        return " (only PNG and JPEG textures are supported)";
    return "";
}

}  // namespace

bool isSupportedExtension(const std::string& name) {
    for (std::string_view s : kSupported)
        if (s == name) return true;
    return false;
}

void checkRequiredExtensions(const std::vector<std::string>& required) {
    for (const std::string& name : required)
        if (!isSupportedExtension(name))
            failf("required extension {} is not supported{}", printableUri(name), why(name));
}

void warnAboutIgnoredExtensions(LoadContext& ctx) {
    for (const std::string& name : ctx.model.extensionsUsed)
        if (!isSupportedExtension(name))
            ctx.warn("extension " + printableUri(name) + " is used but not supported; ignoring it");
}

}  // namespace partita::gltf
