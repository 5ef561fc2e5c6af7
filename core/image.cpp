#include "image.h"

namespace partita {

Rgb Image::mean() const {
    double s[3] = {0, 0, 0};
    for (size_t i = 0; i < rgb.size(); i += 3)
        for (int k = 0; k < 3; ++k) s[k] += rgb[i + k];
    double n = double(width) * height;
    if (n <= 0) return Rgb(0.0f);
    return {float(s[0] / n), float(s[1] / n), float(s[2] / n)};
}

const Image* LayeredImage::layer(const std::string& name) const {
    for (const auto& l : layers)
        if (l.name == name) return &l.image;
    return nullptr;
}

}  // namespace partita
