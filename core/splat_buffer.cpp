#include "splat_buffer.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "film.h"
#include "tent_filter.h"

namespace partita {

void SplatBuffer::addTent(Vec2f r, PathType type, Rgb value) {
    forEachTentPixel(r, width_, height_, [&](int x, int y, float w) {
        splats_.push_back({uint32_t(y) * uint32_t(width_) + uint32_t(x), type, value * w});
    });
}

void SplatBuffer::sortByPixel() {
    size_t pixels = size_t(width_) * size_t(height_);
    sorted_.resize(splats_.size());
    if (splats_.size() * 8 < pixels) {
        // Few splats (an MCMC chain's round): a comparison sort, not a pass over every pixel.
        sorted_ = splats_;
        std::stable_sort(
            sorted_.begin(), sorted_.end(),
            [](const PixelSplat& a, const PixelSplat& b) { return a.pixel < b.pixel; });
        return;
    }
    // Stable counting sort by pixel.
    starts_.assign(pixels + 1, 0);
    for (const PixelSplat& s : splats_) ++starts_[s.pixel + 1];
    for (size_t p = 0; p < pixels; ++p) starts_[p + 1] += starts_[p];
    for (const PixelSplat& s : splats_) sorted_[starts_[s.pixel]++] = s;
}

void SplatBuffer::flushInto(Film& film, Film* also) {
    if (splats_.empty()) return;
    sortByPixel();
    // Per pixel, per type (in order of first appearance), a double sum; one film add each.
    struct TypeSum {
        PathType type;
        std::array<double, 3> sum;
    };
    std::vector<TypeSum> sums;
    for (size_t begin = 0; begin < sorted_.size();) {
        uint32_t pixel = sorted_[begin].pixel;
        size_t end = begin;
        sums.clear();
        for (; end < sorted_.size() && sorted_[end].pixel == pixel; ++end) {
            const PixelSplat& s = sorted_[end];
            TypeSum* t = nullptr;
            for (TypeSum& candidate : sums)
                if (candidate.type == s.type) t = &candidate;
            if (!t) t = &sums.emplace_back(TypeSum{s.type, {0, 0, 0}});
            for (int k = 0; k < 3; ++k) t->sum[size_t(k)] += double(s.value[k]);
        }
        int x = int(pixel % uint32_t(width_)), y = int(pixel / uint32_t(width_));
        for (const TypeSum& t : sums) {
            const Rgb value(float(t.sum[0]), float(t.sum[1]), float(t.sum[2]));
            film.addSample(x, y, t.type, value);
            if (also) also->addSample(x, y, t.type, value);
        }
        begin = end;
    }
    splats_.clear();
}

}  // namespace partita
