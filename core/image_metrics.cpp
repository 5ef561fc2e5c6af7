#include "image_metrics.h"

#include <cmath>
#include <stdexcept>

#include "film.h"

namespace partita {

namespace {

void requireSameSize(const Image& x, const Image& ref) {
    if (x.width != ref.width || x.height != ref.height || x.rgb.size() != ref.rgb.size())
        throw std::invalid_argument("image is " + std::to_string(x.width) + "x" +
                                    std::to_string(x.height) + ", reference is " +
                                    std::to_string(ref.width) + "x" + std::to_string(ref.height));
}

/// Mean over values of weight(r) * (x - r)^2.
template <class Weight>
double meanSquaredError(const Image& x, const Image& ref, Weight weight) {
    requireSameSize(x, ref);
    if (ref.rgb.empty()) return 0;
    double sum = 0;
    for (size_t i = 0; i < ref.rgb.size(); ++i) {
        double d = double(x.rgb[i]) - double(ref.rgb[i]);
        sum += weight(double(ref.rgb[i])) * d * d;
    }
    return sum / double(ref.rgb.size());
}

double relWeight(double r) { return 1.0 / (r * r + kRelMseEpsilon); }

Image blackLike(const Image& image) { return Image(image.width, image.height); }

/// a = (a + b) / 2.
void averageInto(Image& a, const Image& b) {
    requireSameSize(a, b);
    for (size_t i = 0; i < a.rgb.size(); ++i) a.rgb[i] = 0.5f * (a.rgb[i] + b.rgb[i]);
}

void addInto(Image& a, const Image& b) {
    requireSameSize(a, b);
    for (size_t i = 0; i < a.rgb.size(); ++i) a.rgb[i] += b.rgb[i];
}

/// Moves the layers of `image` that `other` lacks into `image`'s "other".
void foldInto(LayeredImage& image, const LayeredImage& other) {
    Image rest = blackLike(image.combined);
    bool hadRest = false;
    std::vector<ImageLayer> kept;
    for (auto& layer : image.layers) {
        if (layer.name != Film::kOtherLayer && other.layer(layer.name)) {
            kept.push_back(std::move(layer));
        } else {
            addInto(rest, layer.image);
            hadRest = true;
        }
    }
    if (hadRest) kept.push_back({Film::kOtherLayer, std::move(rest)});
    image.layers = std::move(kept);
}

LayerError halfSplit(const std::string& name, const Image& a, const Image& b) {
    requireSameSize(a, b);
    if (a.rgb.empty()) return {name, 0, 0};
    double squared = 0, relative = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
        // (a - b) / 2 is distributed as the deviation of the mean from its expectation.
        double d = 0.5 * (double(a.rgb[i]) - double(b.rgb[i]));
        double m = 0.5 * (double(a.rgb[i]) + double(b.rgb[i]));
        squared += d * d;
        relative += d * d * relWeight(m);
    }
    double n = double(a.rgb.size());
    return {name, std::sqrt(squared / n), relative / n};
}

}  // namespace

double rmse(const Image& x, const Image& ref) {
    return std::sqrt(meanSquaredError(x, ref, [](double) { return 1.0; }));
}

double relMse(const Image& x, const Image& ref) { return meanSquaredError(x, ref, relWeight); }

double luminanceSquaredDifference(const Image& a, const Image& b) {
    double sum = 0;
    for (size_t i = 0; i + 2 < a.rgb.size() && i + 2 < b.rgb.size(); i += 3) {
        const double d = double(luminance(Rgb(a.rgb[i], a.rgb[i + 1], a.rgb[i + 2]))) -
                         double(luminance(Rgb(b.rgb[i], b.rgb[i + 1], b.rgb[i + 2])));
        sum += d * d;
    }
    return sum;
}

std::vector<LayerError> compareLayers(const LayeredImage& x, const LayeredImage& ref) {
    std::vector<LayerError> out;
    out.push_back(
        {kCombinedLayerName, rmse(x.combined, ref.combined), relMse(x.combined, ref.combined)});
    for (const auto& layer : ref.layers)
        if (const Image* mine = x.layer(layer.name); mine && layer.name != Film::kOtherLayer)
            out.push_back({layer.name, rmse(*mine, layer.image), relMse(*mine, layer.image)});
    return out;
}

void foldUnsharedLayers(LayeredImage& a, LayeredImage& b) {
    if (!a.layer(Film::kOtherLayer) && !b.layer(Film::kOtherLayer)) return;
    foldInto(a, b);  // now a's types are among b's
    foldInto(b, a);  // and b's among a's
}

LayeredImage meanOfTwo(LayeredImage a, const LayeredImage& b) {
    averageInto(a.combined, b.combined);
    Image zero = blackLike(a.combined);
    for (auto& layer : a.layers) {
        const Image* other = b.layer(layer.name);
        averageInto(layer.image, other ? *other : zero);
    }
    for (const auto& layer : b.layers) {
        if (a.layer(layer.name)) continue;
        Image half = zero;
        averageInto(half, layer.image);
        a.layers.push_back({layer.name, std::move(half)});
    }
    return a;
}

std::vector<LayerError> halfSplitError(const LayeredImage& a, const LayeredImage& b) {
    std::vector<LayerError> out;
    out.push_back(halfSplit(kCombinedLayerName, a.combined, b.combined));
    Image zero = blackLike(a.combined);
    for (const auto& layer : a.layers) {
        const Image* other = b.layer(layer.name);
        out.push_back(halfSplit(layer.name, layer.image, other ? *other : zero));
    }
    for (const auto& layer : b.layers)
        if (!a.layer(layer.name)) out.push_back(halfSplit(layer.name, zero, layer.image));
    return out;
}

}  // namespace partita
