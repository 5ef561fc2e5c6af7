// Result images as the CLI reads and measures them, through the core: readExr (image_io.h) and
// the RMSE and relMSE of image_metrics.h, with their failures as CliError naming the file.
#pragma once

#include <filesystem>
#include <map>
#include <string>

#include "image.h"

namespace partita::cli {

/// core's readExr; a CliError naming the file when it cannot be read.
LayeredImage readResultExr(const std::filesystem::path& path,
                           std::map<std::string, std::string>* attributes = nullptr);

struct ErrorMetrics {
    double rmse = 0, relMse = 0;
};

/// core's rmse and relMse of `image` against `reference`; a CliError when the sizes differ.
ErrorMetrics imageError(const Image& image, const Image& reference);

}  // namespace partita::cli
