#include "gltf/gltf_materials.h"

#include <cfloat>
#include <cmath>

#include "gltf/gltf_common.h"
#include "gltf/gltf_textures.h"

namespace partita::gltf {

namespace {

/// A texture reference however the file spells it: a tinygltf::TextureInfo for core slots, a
/// Value for slots inside material extensions (tinygltf leaves those unparsed).
struct TextureSlot {
    int index = -1;
    int texCoord = 0;
    const tinygltf::Value* transform = nullptr;  // KHR_texture_transform, if present
};

TextureSlot slotFrom(const tinygltf::TextureInfo& info) {
    return {info.index, info.texCoord, findExtension(info.extensions, "KHR_texture_transform")};
}

TextureSlot slotFrom(const tinygltf::Value& info, const std::string& what) {
    TextureSlot slot;
    std::optional<int> index = intMember(info, "index");
    if (!index) failf("{}: texture reference has no valid \"index\"", what);
    slot.index = *index;
    slot.texCoord = intMember(info, "texCoord").value_or(0);
    if (const tinygltf::Value* ext = member(info, "extensions"))
        slot.transform = member(*ext, "KHR_texture_transform");
    return slot;
}

/// Reads `count` numbers of the array `key` into `out`, keeping `out` when absent or malformed.
template <size_t N>
void readNumbers(const tinygltf::Value& object, const char* key, float (&out)[N]) {
    const tinygltf::Value* array = member(object, key);
    if (!array || !array->IsArray() || array->ArrayLen() != N) return;
    for (size_t i = 0; i < N; ++i) {
        const tinygltf::Value& v = array->Get(int(i));
        if (v.IsNumber()) out[i] = clampedFloat(v.GetNumberAsDouble(), -FLT_MAX, FLT_MAX, out[i]);
    }
}

void applyTextureTransform(const tinygltf::Value& t, TextureRef& ref) {
    ref.hasTransform = true;
    float offset[2] = {0, 0}, scale[2] = {1, 1};
    readNumbers(t, "offset", offset);
    readNumbers(t, "scale", scale);
    ref.offset = {offset[0], offset[1]};
    ref.scale = {scale[0], scale[1]};
    ref.rotation = clampedFloat(numberMember(t, "rotation").value_or(0.0), -FLT_MAX, FLT_MAX, 0);
    if (std::optional<int> texCoord = intMember(t, "texCoord")) ref.texCoord = *texCoord;
}

TextureRef textureRef(LoadContext& ctx, TextureCache& textures, const TextureSlot& slot,
                      ColorSpace space, const std::string& what) {
    TextureRef ref;
    if (slot.index == -1) return ref;
    ref.texture = textures.get(slot.index, space, what);
    ref.texCoord = slot.texCoord;
    if (slot.transform) applyTextureTransform(*slot.transform, ref);
    if (ref.texCoord != 0 && ref.texCoord != 1) {
        ctx.warn(
            fmt::format("{}: TEXCOORD_{} is not supported; using TEXCOORD_0", what, ref.texCoord));
        ref.texCoord = 0;
    }
    return ref;
}

/// A factor in [lo, hi]; out-of-range or NaN values are clamped / defaulted with a warning.
float factor(LoadContext& ctx, double value, float lo, float hi, float fallback,
             const std::string& what) {
    float f = clampedFloat(value, lo, hi, fallback);
    if (!(value >= double(lo) && value <= double(hi)))
        ctx.warn(fmt::format("{}: {} is outside [{}, {}]; using {}", what, value, lo, hi, f));
    return f;
}

Rgb colorFactor(LoadContext& ctx, const std::vector<double>& v, Rgb fallback,
                const std::string& what) {
    if (v.size() < 3) return fallback;
    return {factor(ctx, v[0], 0, 1, fallback.x, what), factor(ctx, v[1], 0, 1, fallback.y, what),
            factor(ctx, v[2], 0, 1, fallback.z, what)};
}

void convertPbr(LoadContext& ctx, TextureCache& textures, const tinygltf::Material& src,
                const std::string& what, Material& m) {
    const tinygltf::PbrMetallicRoughness& pbr = src.pbrMetallicRoughness;
    m.baseColor = colorFactor(ctx, pbr.baseColorFactor, Rgb(1.f), what + " baseColorFactor");
    if (pbr.baseColorFactor.size() == 4)
        m.baseAlpha = factor(ctx, pbr.baseColorFactor[3], 0, 1, 1, what + " baseColorFactor");
    m.metallic = factor(ctx, pbr.metallicFactor, 0, 1, 1, what + " metallicFactor");
    m.roughness = factor(ctx, pbr.roughnessFactor, 0, 1, 1, what + " roughnessFactor");
    m.baseColorTexture = textureRef(ctx, textures, slotFrom(pbr.baseColorTexture), ColorSpace::Srgb,
                                    what + " baseColorTexture");
    m.metallicRoughnessTexture = textureRef(ctx, textures, slotFrom(pbr.metallicRoughnessTexture),
                                            ColorSpace::Linear, what + " metallicRoughnessTexture");
}

void convertEmission(LoadContext& ctx, TextureCache& textures, const tinygltf::Material& src,
                     const std::string& what, Material& m) {
    m.emissiveFactor = colorFactor(ctx, src.emissiveFactor, Rgb(0.f), what + " emissiveFactor");
    m.emissiveTexture = textureRef(ctx, textures, slotFrom(src.emissiveTexture), ColorSpace::Srgb,
                                   what + " emissiveTexture");
    if (const tinygltf::Value* ext =
            findExtension(src.extensions, "KHR_materials_emissive_strength"))
        if (std::optional<double> s = numberMember(*ext, "emissiveStrength"))
            m.emissiveStrength = factor(ctx, *s, 0, FLT_MAX, 1, what + " emissiveStrength");
}

void convertTransmission(LoadContext& ctx, TextureCache& textures, const tinygltf::Material& src,
                         const std::string& what, Material& m) {
    const tinygltf::Value* ext = findExtension(src.extensions, "KHR_materials_transmission");
    if (!ext) return;
    if (std::optional<double> t = numberMember(*ext, "transmissionFactor"))
        m.transmission = factor(ctx, *t, 0, 1, 0, what + " transmissionFactor");
    if (const tinygltf::Value* tex = member(*ext, "transmissionTexture"))
        m.transmissionTexture = textureRef(ctx, textures, slotFrom(*tex, what), ColorSpace::Linear,
                                           what + " transmissionTexture");
}

void convertIor(LoadContext& ctx, const tinygltf::Material& src, const std::string& what,
                Material& m) {
    const tinygltf::Value* ext = findExtension(src.extensions, "KHR_materials_ior");
    if (!ext) return;
    std::optional<double> ior = numberMember(*ext, "ior");
    if (!ior) return;
    // ior >= 1 is a physical dielectric; the extension's special value 0 and anything below 1
    // has no meaning for our BSDFs.
    if (std::isfinite(*ior) && *ior >= 1.0 && *ior <= 1e6)
        m.ior = float(*ior);
    else
        ctx.warn(fmt::format("{}: ior {} is not supported; using 1.5", what, *ior));
}

void convertVolume(LoadContext& ctx, const tinygltf::Material& src, const std::string& what,
                   Material& m) {
    const tinygltf::Value* ext = findExtension(src.extensions, "KHR_materials_volume");
    if (!ext) return;
    m.hasVolume = true;
    float rgb[3] = {1, 1, 1};
    readNumbers(*ext, "attenuationColor", rgb);
    m.attenuationColor = {factor(ctx, rgb[0], 0, 1, 1, what + " attenuationColor"),
                          factor(ctx, rgb[1], 0, 1, 1, what + " attenuationColor"),
                          factor(ctx, rgb[2], 0, 1, 1, what + " attenuationColor")};
    if (std::optional<double> d = numberMember(*ext, "attenuationDistance")) {
        if (*d > 0)
            m.attenuationDistance = toFloat(*d);
        else
            ctx.warn(
                fmt::format("{}: attenuationDistance {} is not positive; ignoring it", what, *d));
    }
}

}  // namespace

Material convertMaterial(LoadContext& ctx, TextureCache& textures, int materialIndex) {
    const tinygltf::Material& src = checkedAt(ctx.model.materials, materialIndex, "material");
    std::string what = "material " + std::to_string(materialIndex);
    Material m;
    m.name = src.name.empty() ? what : src.name;
    m.doubleSided = src.doubleSided;
    convertPbr(ctx, textures, src, what, m);
    convertEmission(ctx, textures, src, what, m);
    convertTransmission(ctx, textures, src, what, m);
    convertIor(ctx, src, what, m);
    convertVolume(ctx, src, what, m);
    return m;
}

}  // namespace partita::gltf
