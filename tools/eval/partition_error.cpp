#include "eval/partition_error.h"

#include <cmath>
#include <stdexcept>

#include "film.h"
#include "image_metrics.h"
#include "partition/partition.h"
#include "partition/type_pattern.h"
#include "path_type.h"

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

Image partitionLayer(const LayeredImage& image, const std::string& name, bool directApart,
                     bool& complete) {
    if (const Image* layer = name == Film::kOtherLayer ? nullptr : image.layer(name)) {
        complete = true;
        return *layer;
    }
    Image sum(image.combined.width, image.combined.height);
    complete = false;
    // What the render's partition holds (Partition::holds): the direct-light types, or a
    // class's types less those when the direct light is apart.
    Partition partition;
    partition.direct = name == kDirectLabel;
    partition.directApart = directApart && !partition.direct;
    TypePattern pattern;
    if (!partition.direct &&
        (name == Film::kOtherLayer || !TypePattern::parse(name, pattern) || pattern.isExact()))
        return sum;  // a type the image lacks: black
    partition.patterns = {pattern};
    for (const ImageLayer& layer : image.layers) {
        PathType t;
        if (!PathType::parse(layer.name, t) || !partition.holds(t)) continue;
        for (size_t i = 0; i < sum.rgb.size() && i < layer.image.rgb.size(); ++i)
            sum.rgb[i] += layer.image.rgb[i];
    }
    complete = !image.layer(Film::kOtherLayer);
    return sum;
}

std::vector<PartitionError> partitionErrors(const LayeredImage& render,
                                            const std::vector<std::string>& partitions,
                                            const LayeredImage& reference) {
    const Image& refCombined = reference.combined;
    requireSize(render.combined, refCombined, "the render");
    double combinedSquared = squaredError(render.combined, refCombined);
    double values = double(refCombined.rgb.size());
    // Each partition's reference; the complement's is the combined reference less the others'.
    // When a partition's reference may lie partly in the reference's "other", the complement's
    // reference then holds that part too: not a reference of the complement.
    std::vector<Image> references;
    std::vector<bool> complete;
    bool directApart = false;
    for (const auto& name : partitions) directApart = directApart || name == kDirectLabel;
    Image rest = refCombined;
    bool restComplete = true;
    for (const auto& name : partitions) {
        bool whole = true;
        references.push_back(name == kComplementLabel
                                 ? Image(refCombined.width, refCombined.height)
                                 : partitionLayer(reference, name, directApart, whole));
        complete.push_back(whole);
        if (name == kComplementLabel) continue;
        restComplete = restComplete && whole;
        for (size_t i = 0; i < rest.rgb.size(); ++i) rest.rgb[i] -= references.back().rgb[i];
    }
    std::vector<PartitionError> out;
    for (size_t g = 0; g < partitions.size(); ++g) {
        const std::string& name = partitions[g];
        const Image* mine = render.layer(name);
        if (!mine) throw std::invalid_argument("the render has no layer '" + name + "'");
        requireSize(*mine, refCombined, "layer " + name);
        PartitionError e;
        e.layer = name;
        const bool isComplement = name == kComplementLabel;
        const Image& ref = isComplement ? rest : references[g];
        e.inReference =
            isComplement ? restComplete || !reference.layer(Film::kOtherLayer) : complete[g];
        double squared = 0, relative = 0;
        for (size_t i = 0; i < refCombined.rgb.size(); ++i) {
            const double r = double(ref.rgb[i]);
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
