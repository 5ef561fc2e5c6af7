// Reading and writing images: multi-layer float EXR for results, 8-bit sRGB PNG for previews.
//
// OpenImageIO does the work, but its headers stay out of this one: an OIIO header and a
// generated protobuf header in one translation unit do not compile (see DESIGN.md), and the
// service includes this file next to its generated code.
//
// Files are written atomically: into "<path>.tmp-<pid>-<n>" in the same folder, flushed to
// disk, then renamed over `path`, so a reader (or a restarted daemon) sees either the old file
// or the complete new one. Every failure throws std::runtime_error naming the file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "image.h"

namespace partita {

/// Write `image` as one 32-bit float EXR: channels R, G, B for `combined`, then "<layer>.R",
/// "<layer>.G", "<layer>.B" per layer (every layer must have the size of `combined`). Each
/// metadata entry becomes a string attribute of the header. The layer order is kept in the
/// attribute "partita:layers" (EXR stores channels sorted by name). Lossless ZIP compression.
void writeExr(const std::filesystem::path& path, const LayeredImage& image,
              const std::map<std::string, std::string>& metadata = {});

/// Read an EXR written by writeExr, in its layer order. Any other image OpenImageIO reads is
/// accepted as just `combined`: channels R, G, B (alpha and other channels ignored), else the
/// first three channels, a single channel replicated to grey. Values are returned as stored
/// (an 8-bit file gives its normalised code values, no sRGB decoding). If `metadata` is given
/// it receives every string attribute of the file's header (including OIIO's own, such as
/// "compression"), except "partita:layers".
/// `maxPixels` (> 0): an image of more pixels is refused from its header, before anything is
/// decoded.
LayeredImage readExr(const std::filesystem::path& path,
                     std::map<std::string, std::string>* metadata = nullptr, size_t maxPixels = 0);

/// An image's size as its header gives it, without decoding the pixels.
struct ImageHeader {
    int width = 0, height = 0, channels = 0;
    size_t pixels() const { return size_t(width) * size_t(height); }
};

/// The header of the image in `bytes`, a file named `name` (its extension names the format to
/// OpenImageIO): what a request's uploaded image will cost, known before it is decoded.
/// std::runtime_error naming `name` when it is not an image OpenImageIO reads.
ImageHeader readImageHeader(std::span<const uint8_t> bytes, const std::string& name);

/// 8-bit sRGB PNG: each channel scaled by 2^exposureStops, clamped to [0, 1] (NaN as 0),
/// encoded with the exact piecewise sRGB curve and rounded to the nearest code value, no
/// dithering.
void writePng(const std::filesystem::path& path, const Image& image, float exposureStops = 0);

/// How encodePng compresses. Every mode gives the same pixels; only size and speed differ.
struct PngOptions {
    /// false: OpenImageIO's defaults (zlib level 6, adaptive filters; what writePng writes).
    /// true: unfiltered rows and zlib's run-length strategy (Z_RLE): several times faster for a
    /// somewhat larger file (preview frames, one PNG per layer, encoded while a render runs).
    bool fast = false;
};

/// The bytes of the PNG that writePng would write (for streaming preview frames); with
/// `options.fast`, the same pixels compressed faster.
std::vector<uint8_t> encodePng(const Image& image, float exposureStops = 0,
                               const PngOptions& options = {});

/// The 8-bit sRGB code value of one linear channel value (already exposed): the transfer that
/// writePng applies.
uint8_t encodeSrgb8(float linear);

/// Exposure in stops that maps the 99th percentile of the non-zero pixel luminances to 0.9, so
/// that a preview of any scene looks reasonable. 0 for an image without positive luminance.
float autoExposure(const Image& image);

}  // namespace partita
