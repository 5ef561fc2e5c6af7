// glTF materials to partita::Material: pbrMetallicRoughness with its textures, emission
// (factor x texture x KHR_materials_emissive_strength), KHR_materials_transmission,
// KHR_materials_ior, KHR_materials_volume, doubleSided, and KHR_texture_transform on every
// texture reference. Out-of-range factors are clamped with a warning.
#pragma once

#include "material.h"

namespace partita::gltf {

struct LoadContext;
class TextureCache;

Material convertMaterial(LoadContext& ctx, TextureCache& textures, int materialIndex);

}  // namespace partita::gltf
