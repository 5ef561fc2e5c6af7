#include "algorithm_parameters.h"

#include <map>

namespace partita::server {

std::vector<std::string> algorithmParameters(const std::string& algorithm) {
    // Every algorithm reads the image size, the seed, the depth limit and a time budget; then its
    // native budget unit, and the method's own parameters (paper.md: K, |Y'|, R, epsilon).
    static const std::vector<std::string> common = {"width", "height", "seed", "max-depth",
                                                    "seconds"};
    static const std::map<std::string, std::vector<std::string>> own = {
        {"pt", {"spp"}},
        {"bdpt", {"spp"}},
        {"mlt", {"mpp", "bootstrap"}},
        {"partitioned", {"mpp", "k", "prepass", "bootstrap"}},
        {"guided", {"mpp", "k", "y", "radius", "epsilon", "prepass", "bootstrap"}},
    };
    auto it = own.find(algorithm);
    if (it == own.end()) return {};
    std::vector<std::string> out = common;
    out.insert(out.end(), it->second.begin(), it->second.end());
    return out;
}

}  // namespace partita::server
