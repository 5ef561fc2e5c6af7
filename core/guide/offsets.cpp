#include "guide/offsets.h"

#include <cmath>
#include <stdexcept>

namespace partita {

namespace {

/// The radical inverse of i in `base`: the Halton sequence's coordinate.
double radicalInverse(unsigned i, unsigned base) {
    double inverse = 1.0 / base, scale = inverse, value = 0;
    for (; i > 0; i /= base, scale *= inverse) value += double(i % base) * scale;
    return value;
}

}  // namespace

std::vector<PixelOffset> guideOffsets(int count, float radius) {
    if (count < 1) throw std::invalid_argument("|Y'| must be at least 1");
    if (!(radius >= 0) || !std::isfinite(radius))
        throw std::invalid_argument("the guide radius must be finite and non-negative");
    int half = (count - 1) / 2;
    int centres = count - 2 * half;  // 1 for odd |Y'|, 2 for even
    std::vector<PixelOffset> first;
    for (int k = 0; k < half; ++k) {
        // Halton index k + 1: index 0 is the origin, already the centre.
        double zx = radicalInverse(unsigned(k + 1), 2), zy = radicalInverse(unsigned(k + 1), 3);
        double r = radius * zx * zx, theta = 2 * M_PI * zy;
        first.push_back(
            {int(std::lround(r * std::cos(theta))), int(std::lround(r * std::sin(theta)))});
    }
    std::vector<PixelOffset> delta = first;
    delta.insert(delta.end(), size_t(centres), PixelOffset{0, 0});
    for (const PixelOffset& o : first) delta.push_back({-o.dx, -o.dy});
    return delta;
}

}  // namespace partita
