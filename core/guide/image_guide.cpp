#include "guide/image_guide.h"

#include <cmath>

namespace partita {

std::vector<float> relativeToMean(const std::vector<float>& d) {
    double sum = 0;
    size_t positive = 0;
    for (float v : d)
        if (v > 0) {
            sum += double(v);
            ++positive;
        }
    std::vector<float> out(d.size(), 0.0f);
    if (positive == 0) return out;
    double scale = double(positive) / sum;
    for (size_t i = 0; i < d.size(); ++i) out[i] = float(double(d[i]) * scale);
    return out;
}

double ImageGuide::supportFraction() const {
    size_t ones = 0;
    for (int y = 0; y < height(); ++y)
        for (int x = 0; x < width(); ++x) ones += masks_->above(partition_, x, y);
    size_t pixels = size_t(width()) * size_t(height());
    return pixels ? double(ones) / double(pixels) : 0;
}

}  // namespace partita
