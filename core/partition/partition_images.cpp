#include "partition/partition_images.h"

#include <algorithm>
#include <map>
#include <stdexcept>

namespace partita {

std::vector<std::vector<float>> partitionPrepassImages(const PrepassResult& prepass,
                                                       const std::vector<Partition>& partitions,
                                                       int width, int height) {
    size_t pixels = size_t(std::max(0, width)) * size_t(std::max(0, height));
    std::vector<std::vector<float>> images(partitions.size(), std::vector<float>(pixels, 0.0f));
    if (pixels == 0 || prepass.samplesB == 0) return images;
    // Each type's partition (the one that holds it; none when there is no complement), looked
    // up once per type.
    std::map<PathType, size_t> partitionOf;
    auto lookUp = [&](const PathType& t) {
        auto [it, added] = partitionOf.emplace(t, partitions.size());
        if (added)
            for (size_t g = 0; g < partitions.size(); ++g)
                if (partitions[g].holds(t)) {
                    it->second = g;
                    break;
                }
        return it->second;
    };
    // Added in record order (sample order): the images do not depend on the thread count. At
    // 1280x720 a pixel gets a handful of records (the default pre-pass draws ~0.1 sample a
    // pixel); float sums keep the mean b_i to ~1e-6 even at many records a pixel.
    float scale = float(double(pixels) / double(prepass.samplesB));
    PathType lastType;
    size_t lastPartition = partitions.size();
    bool haveLast = false;
    for (const BootstrapCandidate& c : prepass.candidatesB) {
        if (!haveLast || !(c.type == lastType)) {
            lastPartition = lookUp(c.type);
            lastType = c.type;
            haveLast = true;
        }
        if (lastPartition == partitions.size()) continue;  // in no partition (no complement)
        if (c.pixel >= pixels)
            throw std::invalid_argument("a pre-pass record's pixel lies outside the image");
        images[lastPartition][c.pixel] += c.weight * scale;
    }
    return images;
}

}  // namespace partita
