// Fast PNG encoding for preview frames. The pixels are exactly those of partita::encodePng (the
// same exposure scale and sRGB code values, via partita::encodeSrgb8), but compressed for speed:
// one "Sub" filter per row and zlib level 1. OpenImageIO's writer, which encodePng uses, takes
// ~20-40 ms per 320x240 layer on this project's machines; a frame has a PNG per path-type layer
// (up to 33), and previews must neither lag nor eat the render's CPU.
#pragma once

#include <string>

#include "image.h"

namespace partita::server {

/// An 8-bit RGB PNG (with an sRGB chunk) of `image` scaled by 2^exposureStops. Throws
/// std::runtime_error for an empty or malformed image.
std::string encodePreviewPng(const Image& image, float exposureStops);

}  // namespace partita::server
