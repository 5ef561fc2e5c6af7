// Image decoding for glTF textures: the encoded bytes come from a bufferView (bounds-checked) or
// from a uri read through the resolver; PNG and JPEG are decoded with tinygltf's stb-based
// loader after their header dimensions are checked against the pixel limit.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace partita::gltf {

struct LoadContext;
class TinyGltfIo;

/// RGBA values in [0, 1] as stored in the file (no colour-space conversion yet).
/// Texels as RGBA (grey replicated, missing alpha opaque), row 0 at the top: the bytes of an
/// 8-bit image, or values in [0, 1] for a 16-bit one; the other vector is empty.
struct DecodedImage {
    int width = 0, height = 0;
    std::vector<uint8_t> rgba8;  // width * height * 4, for 8-bit images
    std::vector<float> rgba;     // width * height * 4, for 16-bit images
};

/// Decodes glTF image `index`; a missing, unreadable, oversized or undecodable image fails with
/// a message naming it.
DecodedImage decodeImage(const LoadContext& ctx, const TinyGltfIo& io, int index);

struct ImageSize {
    uint32_t width = 0, height = 0;
};
/// Dimensions from a PNG or JPEG header, without decoding; fails on anything else.
ImageSize sniffImageSize(const uint8_t* data, size_t size, const std::string& what);

}  // namespace partita::gltf
