#include "eval/partition_error.h"

#include <cmath>
#include <stdexcept>

#include "film.h"
#include "image_metrics.h"
#include "partition/partition.h"

namespace partita::eval {

namespace {

void requireSize(const Image& image, const Image& like, const std::string& what) {
    if (image.width != like.width || image.height != like.height ||
        image.rgb.size() != like.rgb.size())
        throw std::invalid_argument(what + " is " + std::to_string(image.width) + "x" +
                                    std::to_string(image.height) + ", the reference " +
                                    std::to_string(like.width) + "x" + std::to_string(like.height));
}

double squaredError(const Image& x, const Image& ref) {
    double sum = 0;
    for (size_t i = 0; i < ref.rgb.size(); ++i) {
        double d = double(x.rgb[i]) - double(ref.rgb[i]);
        sum += d * d;
    }
    return sum;
}

}  // namespace

std::vector<std::string> partitionLabels(const std::map<std::string, std::string>& labels) {
    std::vector<std::string> out;
    for (size_t g = 0;; ++g) {
        auto it = labels.find("partition_" + std::to_string(g) + "_type");
        if (it == labels.end()) return out;
        out.push_back(it->second);
    }
}

std::vector<PartitionError> partitionErrors(const LayeredImage& render,
                                            const std::vector<std::string>& partitions,
                                            const LayeredImage& reference) {
    const Image& refCombined = reference.combined;
    requireSize(render.combined, refCombined, "the render");
    double combinedSquared = squaredError(render.combined, refCombined);
    double values = double(refCombined.rgb.size());
    // The complement's reference subtracts the reference layers of the partitions' own types.
    // When the reference lacks one of them and has an "other", that type may be in its "other",
    // and the complement's reference then holds it too: not a reference of the complement.
    std::vector<const Image*> typeReferences;
    bool complete = true;
    for (const auto& name : partitions)
        if (name != kComplementLabel) {
            const Image* r = name == Film::kOtherLayer ? nullptr : reference.layer(name);
            if (r)
                typeReferences.push_back(r);
            else
                complete = false;
        }
    bool complementInReference = complete || !reference.layer(Film::kOtherLayer);
    std::vector<PartitionError> out;
    for (const auto& name : partitions) {
        const Image* mine = render.layer(name);
        if (!mine) throw std::invalid_argument("the render has no layer '" + name + "'");
        requireSize(*mine, refCombined, "layer " + name);
        PartitionError e;
        e.layer = name;
        const Image* ref =
            name == kComplementLabel || name == Film::kOtherLayer ? nullptr : reference.layer(name);
        e.inReference = name == kComplementLabel ? complementInReference : ref != nullptr;
        double squared = 0, relative = 0;
        for (size_t i = 0; i < refCombined.rgb.size(); ++i) {
            double r = 0;
            if (name == kComplementLabel) {
                r = double(refCombined.rgb[i]);
                for (const Image* t : typeReferences) r -= double(t->rgb[i]);
            } else if (ref) {
                r = double(ref->rgb[i]);
            }
            double d = double(mine->rgb[i]) - r;
            squared += d * d;
            relative += d * d / (r * r + kRelMseEpsilon);
        }
        e.squaredError = squared;
        e.rmse = values > 0 ? std::sqrt(squared / values) : 0;
        e.relMse = values > 0 ? relative / values : 0;
        e.share = combinedSquared > 0 ? squared / combinedSquared : 0;
        out.push_back(e);
    }
    return out;
}

}  // namespace partita::eval
