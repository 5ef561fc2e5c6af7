// The core rendering in the test process, to compare the daemon's results with, and image
// helpers for results that arrive as bytes.
#pragma once

#include <filesystem>
#include <string>

#include "image.h"
#include "service_client.h"

namespace partita::test {

/// runRender of `algorithm` on a scene file with the settings the daemon derives from
/// sceneSpec(), the budget `spp` in the algorithm's native unit (samples or mutations per
/// pixel).
LayeredImage renderInProcess(const fs::path& sceneFile, int width, int height, double spp,
                             uint64_t seed, const std::string& algorithm = "pt");

/// An image received as bytes (EXR, or PNG with name "x.png"), read with partita::readExr.
LayeredImage readExrBytes(const std::string& bytes, const std::string& name = "result.exr");

/// A preview frame's raw float layers as an image ("combined" first, the rest as layers).
LayeredImage frameImage(const pb::PreviewFrame& frame);

/// "" when equal bit for bit (sizes, layer names and order, every float), else the first
/// difference.
std::string compareImages(const LayeredImage& a, const LayeredImage& b);

}  // namespace partita::test
