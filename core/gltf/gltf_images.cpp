#include "gltf/gltf_images.h"

#include <climits>
#include <cstring>

#include "gltf/gltf_common.h"
#include "gltf/gltf_io.h"

namespace partita::gltf {

namespace {

uint32_t be16(const uint8_t* p) { return uint32_t(p[0]) << 8 | p[1]; }
uint32_t be32(const uint8_t* p) { return be16(p) << 16 | be16(p + 2); }

ImageSize pngSize(const uint8_t* data, size_t size, const std::string& what) {
    if (size < 24 || std::memcmp(data + 12, "IHDR", 4) != 0)
        failf("{}: PNG is truncated or has no IHDR header", what);
    return {be32(data + 16), be32(data + 20)};
}

bool isJpegStartOfFrame(uint8_t marker) {
    // SOF0..SOF15 except DHT (C4), JPG (C8) and DAC (CC).
    return marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
}

ImageSize jpegSize(const uint8_t* data, size_t size, const std::string& what) {
    size_t i = 2;
    while (i < size) {
        if (data[i] != 0xFF) break;
        while (i < size && data[i] == 0xFF) ++i;  // fill bytes
        if (i >= size) break;
        uint8_t marker = data[i++];
        if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8)) continue;  // no payload
        if (marker == 0xD9 || marker == 0xDA || i + 2 > size) break;  // image data before a frame
        uint32_t length = be16(data + i);
        if (length < 2) break;
        if (isJpegStartOfFrame(marker)) {
            if (i + 7 > size) break;
            return {be16(data + i + 5), be16(data + i + 3)};
        }
        i += length;
    }
    failf("{}: JPEG is truncated or has no frame header", what);
}

/// Where the encoded bytes of `image` are: its bufferView, or what TinyGltfIo kept from its uri.
std::pair<const uint8_t*, size_t> encodedBytes(const LoadContext& ctx, const TinyGltfIo& io,
                                               const tinygltf::Image& image,
                                               const std::string& what) {
    if (image.bufferView >= 0) {
        const tinygltf::BufferView& view =
            checkedAt(ctx.model.bufferViews, image.bufferView, "bufferView");
        const tinygltf::Buffer& buffer = checkedAt(ctx.model.buffers, view.buffer, "buffer");
        if (view.byteOffset > buffer.data.size() ||
            view.byteLength > buffer.data.size() - view.byteOffset)
            failf("{}: bufferView {} is out of bounds of buffer {}", what, image.bufferView,
                  view.buffer);
        return {buffer.data.data() + view.byteOffset, view.byteLength};
    }
    if (image.image.empty()) {
        std::string why = io.errorFor(decodeUriLikeTinygltf(image.uri));
        if (why.empty()) why = "no data";
        failf("{}: could not be read: {}", what, why);
    }
    return {image.image.data(), image.image.size()};
}

void checkSize(const LoadContext& ctx, ImageSize size, const std::string& what) {
    if (size.width == 0 || size.height == 0) failf("{}: has zero width or height", what);
    if (uint64_t(size.width) * size.height > ctx.limits.maxTexturePixels)
        failf("{}: {}x{} pixels exceed the limit of {} pixels", what, size.width, size.height,
              ctx.limits.maxTexturePixels);
}

/// The channels of pixel p as RGBA: grey replicated to G and B, alpha opaque unless given.
template <typename T>
void expandToRgba(const T* in, int comp, T opaque, T* out) {
    if (comp <= 2) {  // grey (+ alpha)
        out[0] = out[1] = out[2] = in[0];
        out[3] = comp == 2 ? in[1] : opaque;
    } else {
        for (int c = 0; c < 3; ++c) out[c] = in[c];
        out[3] = comp == 4 ? in[3] : opaque;
    }
}

DecodedImage toRgba(const tinygltf::Image& decoded, const std::string& what) {
    int comp = decoded.component, bytesPerChannel = decoded.bits / 8;
    if (decoded.width <= 0 || decoded.height <= 0 || comp < 1 || comp > 4 ||
        (bytesPerChannel != 1 && bytesPerChannel != 2))
        failf("{}: decoder returned an unexpected layout", what);
    size_t pixels = size_t(decoded.width) * size_t(decoded.height);
    if (decoded.image.size() != pixels * size_t(comp) * size_t(bytesPerChannel))
        failf("{}: decoder returned a truncated image", what);
    DecodedImage out;
    out.width = decoded.width;
    out.height = decoded.height;
    if (bytesPerChannel == 1) {
        out.rgba8.resize(pixels * 4);
        for (size_t p = 0; p < pixels; ++p)
            expandToRgba(&decoded.image[p * size_t(comp)], comp, uint8_t(255), &out.rgba8[p * 4]);
        return out;
    }
    out.rgba.resize(pixels * 4);
    for (size_t p = 0; p < pixels; ++p) {
        float v[4];
        for (int c = 0; c < comp; ++c) {
            uint16_t wide;  // stb returns native-endian shorts
            std::memcpy(&wide, &decoded.image[(p * size_t(comp) + size_t(c)) * 2], 2);
            v[c] = float(wide) * (1.f / 65535.f);
        }
        expandToRgba(v, comp, 1.0f, &out.rgba[p * 4]);
    }
    return out;
}

}  // namespace

ImageSize sniffImageSize(const uint8_t* data, size_t size, const std::string& what) {
    static const uint8_t kPng[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
    if (size >= 8 && std::memcmp(data, kPng, 8) == 0) return pngSize(data, size, what);
    if (size >= 3 && data[0] == 0xFF && data[1] == 0xD8 && data[2] == 0xFF)
        return jpegSize(data, size, what);
    failf("{}: not a PNG or JPEG image (the formats glTF 2.0 allows)", what);
}

DecodedImage decodeImage(const LoadContext& ctx, const TinyGltfIo& io, int index) {
    const tinygltf::Image& image = checkedAt(ctx.model.images, index, "image");
    std::string label = !image.name.empty() ? image.name : printableUri(image.uri);
    std::string what = "image " + std::to_string(index) + (label.empty() ? "" : " '" + label + "'");
    auto [data, size] = encodedBytes(ctx, io, image, what);
    if (size > size_t(INT_MAX)) failf("{}: is larger than 2 GiB", what);
    checkSize(ctx, sniffImageSize(data, size, what), what);

    tinygltf::Image decoded;
    std::string err, warn;
    // A null user pointer selects the default options: every image expanded to RGBA.
    if (!tinygltf::LoadImageData(&decoded, index, &err, &warn, 0, 0, data, int(size), nullptr))
        failf("{}: could not be decoded (corrupt or unsupported PNG/JPEG)", what);
    checkSize(ctx, {uint32_t(decoded.width), uint32_t(decoded.height)}, what);
    return toRgba(decoded, what);
}

}  // namespace partita::gltf
