// Image textures as glTF describes them: a decoded image plus sampler state, and a reference
// from a material slot (which UV set, KHR_texture_transform).
#pragma once

#include <array>
#include <cstdint>
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

/// A decoded texture in linear values; the loader keeps one Texture per (image, sampler, colour
/// space) combination it meets.
///
/// The texels (width * height * 4, row 0 at the top, v = 0) are stored in one of two forms.
/// Images with 8 bits per channel, nearly all of them, keep their bytes in `rgba8`: a quarter of
/// the memory of floats, and a quarter of the cache lines a lookup touches. A byte b reads as
/// `colorOf8[b]` in the colour channels (the loader fills it with b / 255, sRGB-decoded for
/// colour textures: exactly what converting every texel at load would give) and b / 255 in
/// alpha. Anything else (16-bit images, textures built in code) is float, in `rgba`.
struct Texture {
    std::string name;
    int width = 0, height = 0;
    std::vector<float> rgba;     // float texels, or empty when rgba8 holds them
    std::vector<uint8_t> rgba8;  // 8-bit texels, or empty
    std::array<float, 256> colorOf8{};
    WrapMode wrapS = WrapMode::Repeat, wrapT = WrapMode::Repeat;
    TextureFilter filter = TextureFilter::Linear;

    /// Texel (x, y), 0 <= x < width and 0 <= y < height, in linear values, whichever the form.
    Rgba texel(int x, int y) const;
    /// One channel (0 to 3: R, G, B, A) of texel (x, y).
    float channel(int x, int y, int c) const {
        Rgba t = texel(x, y);
        return c == 3 ? t.a : t.rgb[c];
    }
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
