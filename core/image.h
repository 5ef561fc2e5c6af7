// A float RGB image and a set of named layers (the combined image plus one per path type).
#pragma once

#include <string>
#include <vector>

#include "math/vec.h"

namespace partita {

struct Image {
    int width = 0, height = 0;
    std::vector<float> rgb;  // width * height * 3, row-major, row 0 at the top

    Image() = default;
    Image(int w, int h) : width(w), height(h), rgb(size_t(w) * h * 3, 0.0f) {}

    Rgb at(int x, int y) const {
        const float* p = &rgb[(size_t(y) * width + x) * 3];
        return {p[0], p[1], p[2]};
    }
    void set(int x, int y, Rgb v) {
        float* p = &rgb[(size_t(y) * width + x) * 3];
        p[0] = v.x;
        p[1] = v.y;
        p[2] = v.z;
    }
    void add(int x, int y, Rgb v) {
        float* p = &rgb[(size_t(y) * width + x) * 3];
        p[0] += v.x;
        p[1] += v.y;
        p[2] += v.z;
    }
    bool empty() const { return rgb.empty(); }
    Rgb mean() const;
};

/// A named layer of a LayeredImage, e.g. "LDSDE" or "other".
struct ImageLayer {
    std::string name;
    Image image;
};

/// What a render produces: the combined radiance and its decomposition into layers. When the
/// layers are complete (no type dropped), they sum to `combined` pixel by pixel.
struct LayeredImage {
    Image combined;
    std::vector<ImageLayer> layers;

    const Image* layer(const std::string& name) const;
};

}  // namespace partita
