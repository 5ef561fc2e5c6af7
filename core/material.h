// A glTF 2.0 material as loaded (pbrMetallicRoughness + the supported KHR extensions). How these
// parameters become a BSDF is written in material_mapping.h beside the code that does it.
#pragma once

#include <string>

#include "math/vec.h"
#include "texture.h"

namespace partita {

struct Material {
    std::string name;

    // pbrMetallicRoughness
    Rgb baseColor{1.0f};
    float baseAlpha = 1.0f;
    TextureRef baseColorTexture;  // sRGB, decoded at load
    float metallic = 1.0f;
    float roughness = 1.0f;
    TextureRef metallicRoughnessTexture;  // linear; G = roughness, B = metallic

    // emission: emissiveFactor x texture x KHR_materials_emissive_strength
    Rgb emissiveFactor{0.0f};
    float emissiveStrength = 1.0f;
    TextureRef emissiveTexture;  // sRGB, decoded at load

    // KHR_materials_transmission + KHR_materials_ior
    float transmission = 0.0f;
    TextureRef transmissionTexture;  // linear; R channel
    float ior = 1.5f;

    // KHR_materials_volume (absorption only; thickness is unused by a ray tracer that sees the
    // real geometry)
    bool hasVolume = false;
    Rgb attenuationColor{1.0f};
    float attenuationDistance = kInf;

    bool doubleSided = false;

    /// Emission without texture: zero means the material never emits.
    Rgb emissionScale() const { return emissiveFactor * emissiveStrength; }
    bool isEmissive() const { return maxComponent(emissionScale()) > 0; }
};

}  // namespace partita
