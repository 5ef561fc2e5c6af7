#include "cli/image_metrics.h"

#include <cmath>

#include "cli/errors.h"

namespace partita::cli {

ErrorMetrics compareImages(const Image& image, const Image& reference) {
    if (image.width != reference.width || image.height != reference.height)
        throw CliError("image is " + std::to_string(image.width) + "x" +
                       std::to_string(image.height) + " but the reference is " +
                       std::to_string(reference.width) + "x" + std::to_string(reference.height));
    const size_t n = image.rgb.size();
    if (n == 0) throw CliError("empty image");
    double se = 0, rel = 0;
    for (size_t i = 0; i < n; ++i) {
        const double x = image.rgb[i], r = reference.rgb[i], d = x - r;
        se += d * d;
        rel += d * d / (r * r + 1e-2);
    }
    return {std::sqrt(se / double(n)), rel / double(n)};
}

}  // namespace partita::cli
