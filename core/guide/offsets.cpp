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

OffsetLanes::OffsetLanes(const std::vector<PixelOffset>& delta) : count(delta.size()) {
    const size_t padded = (count + kLanes - 1) / kLanes * kLanes;
    // -2^20 pixels: off any image (limits are far below), and p + it cannot overflow.
    constexpr int kOffImage = -(1 << 20);
    dx.assign(padded, kOffImage);
    dy.assign(padded, kOffImage);
    for (size_t k = 0; k < count; ++k) {
        dx[k] = delta[k].dx;
        dy[k] = delta[k].dy;
    }
}

std::vector<int> oppositeOffsets(const std::vector<PixelOffset>& delta) {
    std::vector<int> opposite(delta.size(), -1);
    for (size_t k = 0; k < delta.size(); ++k) {
        const PixelOffset back{-delta[k].dx, -delta[k].dy};
        int forwardCount = 0, backCount = 0;
        for (size_t j = 0; j < delta.size(); ++j) {
            forwardCount += delta[j] == delta[k];
            if (delta[j] == back) {
                ++backCount;
                if (opposite[k] < 0) opposite[k] = int(j);
            }
        }
        if (forwardCount != backCount)
            throw std::invalid_argument(
                "the guide's offsets are not symmetric (each shift as often as its negation)");
    }
    return opposite;
}

}  // namespace partita
