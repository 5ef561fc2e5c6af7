// Image textures as glTF describes them: a decoded image plus sampler state, and a reference
// from a material slot (which UV set, KHR_texture_transform).
#pragma once

#include <string>
#include <vector>

#include "math/vec.h"

namespace partita {

enum class WrapMode { Repeat, ClampToEdge, MirroredRepeat };
enum class TextureFilter { Nearest, Linear };

struct Rgba {
    Rgb rgb{1.0f};
    float a = 1.0f;
};

/// A decoded texture in linear values. Colour textures (base colour, emissive) are converted from
/// sRGB when loaded, so lookups never decode; the loader keeps one Texture per (image, sampler,
/// colour space) combination it meets.
struct Texture {
    std::string name;
    int width = 0, height = 0;
    std::vector<float> rgba;  // width * height * 4, row 0 at the top (v = 0)
    WrapMode wrapS = WrapMode::Repeat, wrapT = WrapMode::Repeat;
    TextureFilter filter = TextureFilter::Linear;

    /// Filtered lookup at texture coordinate uv (glTF convention: v grows downwards).
    Rgba lookup(Vec2f uv) const;
};

/// A material slot's reference to a texture.
struct TextureRef {
    int texture = -1;  // index into SceneData::textures, -1 = none
    int texCoord = 0;  // which TEXCOORD_n set (KHR_texture_transform may override it)
    // KHR_texture_transform: uv' = T(offset) * R(rotation) * S(scale) * uv
    bool hasTransform = false;
    Vec2f offset{0, 0};
    float rotation = 0;
    Vec2f scale{1, 1};

    bool valid() const { return texture >= 0; }
    Vec2f transformUv(Vec2f uv) const;
};

}  // namespace partita
