#include "gltf/gltf_textures.h"

#include <algorithm>
#include <cmath>

#include "gltf/gltf_common.h"

namespace partita::gltf {

namespace {

WrapMode wrapMode(LoadContext& ctx, int mode, int sampler) {
    switch (mode) {
        case TINYGLTF_TEXTURE_WRAP_REPEAT:
            return WrapMode::Repeat;
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
            return WrapMode::ClampToEdge;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
            return WrapMode::MirroredRepeat;
        default:
            ctx.warn(fmt::format("sampler {}: unknown wrap mode {}; using REPEAT", sampler, mode));
            return WrapMode::Repeat;
    }
}

/// Only the magnification filter matters: a path tracer samples at most one texel footprint.
TextureFilter filterMode(LoadContext& ctx, int magFilter, int sampler) {
    if (magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST) return TextureFilter::Nearest;
    if (magFilter != TINYGLTF_TEXTURE_FILTER_LINEAR && magFilter != -1)
        ctx.warn(fmt::format("sampler {}: unknown magFilter {}; using LINEAR", sampler, magFilter));
    return TextureFilter::Linear;
}

void applySampler(LoadContext& ctx, int samplerIndex, Texture& texture) {
    if (samplerIndex == -1) return;  // glTF default: repeat, filtering up to the renderer
    const tinygltf::Sampler& sampler = checkedAt(ctx.model.samplers, samplerIndex, "sampler");
    texture.wrapS = wrapMode(ctx, sampler.wrapS, samplerIndex);
    texture.wrapT = wrapMode(ctx, sampler.wrapT, samplerIndex);
    texture.filter = filterMode(ctx, sampler.magFilter, samplerIndex);
}

/// Colour channels of RGBA data; alpha is linear in glTF.
void convertSrgbToLinear(std::vector<float>& rgba) {
    for (size_t i = 0; i < rgba.size(); ++i)
        if (i % 4 != 3) rgba[i] = srgbToLinear(rgba[i]);
}

std::string textureName(const tinygltf::Model& model, int imageIndex) {
    const tinygltf::Image& image = model.images[size_t(imageIndex)];
    if (!image.name.empty()) return image.name;
    if (!image.uri.empty()) return printableUri(image.uri);
    return "image" + std::to_string(imageIndex);
}

}  // namespace

float srgbToLinear(float v) {
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

const DecodedImage& TextureCache::image(int imageIndex) {
    auto it = images_.find(imageIndex);
    if (it == images_.end())
        it = images_.emplace(imageIndex, decodeImage(ctx_, io_, imageIndex)).first;
    return it->second;
}

void TextureCache::chargePixels(const DecodedImage& decoded, const std::string& what) {
    uint64_t pixels = uint64_t(decoded.width) * uint64_t(decoded.height);
    uint64_t limit = ctx_.limits.maxTotalTexturePixels;
    if (pixels > limit - std::min(ctx_.texturePixels, limit))
        failf("{}: textures exceed the limit of {} pixels in all", what, limit);
    ctx_.texturePixels += pixels;
}

int TextureCache::get(int textureIndex, ColorSpace space, const std::string& what) {
    if (textureIndex < 0 || size_t(textureIndex) >= ctx_.model.textures.size())
        failf("{}: texture index {} is out of range (the file has {})", what, textureIndex,
              ctx_.model.textures.size());
    const tinygltf::Texture& gltfTexture = ctx_.model.textures[size_t(textureIndex)];
    if (gltfTexture.source == -1)
        failf("texture {}: has no PNG/JPEG source image (only KTX2/WebP/DDS?)", textureIndex);
    checkedAt(ctx_.model.images, gltfTexture.source, "image");
    auto key = std::make_tuple(gltfTexture.source, gltfTexture.sampler, space);
    if (auto it = textures_.find(key); it != textures_.end()) return it->second;

    const DecodedImage& decoded = image(gltfTexture.source);
    chargePixels(decoded, what);
    Texture texture;
    texture.name = textureName(ctx_.model, gltfTexture.source);
    texture.width = decoded.width;
    texture.height = decoded.height;
    if (!decoded.rgba8.empty()) {
        texture.rgba8 = decoded.rgba8;
        for (int b = 0; b < 256; ++b) {
            float v = float(b) * (1.f / 255.f);
            texture.colorOf8[size_t(b)] = space == ColorSpace::Srgb ? srgbToLinear(v) : v;
        }
    } else {
        texture.rgba = decoded.rgba;
        if (space == ColorSpace::Srgb) convertSrgbToLinear(texture.rgba);
    }
    applySampler(ctx_, gltfTexture.sampler, texture);

    int index = int(ctx_.scene.textures.size());
    ctx_.scene.textures.push_back(std::move(texture));
    textures_.emplace(key, index);
    return index;
}

}  // namespace partita::gltf
