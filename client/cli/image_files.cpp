#include "cli/image_files.h"

#include <stdexcept>

#include "cli/errors.h"
#include "image_io.h"
#include "image_metrics.h"

namespace partita::cli {

LayeredImage readResultExr(const std::filesystem::path& path,
                           std::map<std::string, std::string>* attributes) {
    try {
        return readExr(path, attributes);
    } catch (const std::exception& e) {
        throw CliError("cannot read '" + path.string() + "': " + e.what());
    }
}

ErrorMetrics imageError(const Image& image, const Image& reference) {
    try {
        return {rmse(image, reference), relMse(image, reference)};
    } catch (const std::invalid_argument& e) {
        throw CliError(e.what());
    }
}

}  // namespace partita::cli
