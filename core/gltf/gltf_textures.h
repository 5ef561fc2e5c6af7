// glTF textures (image + sampler) to SceneData::textures: one Texture per (image, sampler,
// colour space), colour textures converted from sRGB to linear once at load.
#pragma once

#include <map>
#include <string>
#include <tuple>

#include "gltf/gltf_images.h"
#include "texture.h"

namespace partita::gltf {

struct LoadContext;
class TinyGltfIo;

enum class ColorSpace { Linear, Srgb };

class TextureCache {
  public:
    TextureCache(LoadContext& ctx, const TinyGltfIo& io) : ctx_(ctx), io_(io) {}

    /// The SceneData::textures index for glTF texture `textureIndex` read in `space`.
    int get(int textureIndex, ColorSpace space, const std::string& what);

  private:
    const DecodedImage& image(int imageIndex);
    /// Counts a new texture against GltfLoadLimits::maxTotalTexturePixels.
    void chargePixels(const DecodedImage& decoded, const std::string& what);

    LoadContext& ctx_;
    const TinyGltfIo& io_;
    std::map<std::tuple<int, int, ColorSpace>, int> textures_;  // (image, sampler, space)
    std::map<int, DecodedImage> images_;
};

/// sRGB transfer function inverse (IEC 61966-2-1).
float srgbToLinear(float v);

}  // namespace partita::gltf
