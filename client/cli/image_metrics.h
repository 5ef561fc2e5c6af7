// Error of an image against a reference, the numbers `compare` and `sweep` print:
//   RMSE   = sqrt(mean over pixels and RGB channels of (x - r)^2)
//   relMSE = mean over pixels and RGB channels of (x - r)^2 / (r^2 + 1e-2)
// (the relative MSE of the rendering literature, with 1e-2 keeping black pixels finite).
#pragma once

#include "image.h"

namespace partita::cli {

struct ErrorMetrics {
    double rmse = 0, relMse = 0;
};

/// Throws CliError when the sizes differ.
ErrorMetrics compareImages(const Image& image, const Image& reference);

}  // namespace partita::cli
