// Reading result EXRs in the CLI without OpenImageIO.
//
// Why not core/image_io.h's readExr: OpenImageIO drags about 300 shared libraries (OpenCV,
// FFmpeg, GStreamer, ...) into the process, which costs ~0.6 s at every start of a command that
// otherwise needs only gRPC (~0.03 s). The files compared here are partitad's results: single-part
// scanline EXRs with float or half channels, ZIP-compressed. This reader handles that format family
// (compression NONE, RLE, ZIPS, ZIP; channel types UINT, HALF, FLOAT; no subsampling) after the
// OpenEXR file-layout document, and refuses anything else (tiled, deep, multi-part, PIZ, PXR24,
// B44, DWA) with a clear error. Its twin for Python is client/python/partita_client/exr.py; the
// tests check both against readExr.
#pragma once

#include <filesystem>
#include <map>
#include <string>

#include "image.h"

namespace partita::cli {

/// As readExr: `combined` from R, G, B (else the first three channels, or one as grey), then
/// every "<layer>.R/G/B" triple in the order of the "partita:layers" attribute, else in channel
/// order. String attributes go to `attributes` when given. Throws CliError naming the file.
LayeredImage readExrFile(const std::filesystem::path& path,
                         std::map<std::string, std::string>* attributes = nullptr);

}  // namespace partita::cli
