#include "sampling.h"

#include <algorithm>
#include <cmath>

namespace partita {

Vec2f sampleConcentricDisk(Vec2f u) {
    float ox = 2 * u.x - 1, oy = 2 * u.y - 1;
    if (ox == 0 && oy == 0) return {0, 0};
    float r, theta;
    if (std::abs(ox) > std::abs(oy)) {
        r = ox;
        theta = (kPi / 4) * (oy / ox);
    } else {
        r = oy;
        theta = kPi / 2 - (kPi / 4) * (ox / oy);
    }
    return {r * std::cos(theta), r * std::sin(theta)};
}

Vec3f sampleCosineHemisphere(Vec2f u) {
    Vec2f d = sampleConcentricDisk(u);
    float z = safeSqrt(1 - d.x * d.x - d.y * d.y);
    return {d.x, d.y, z};
}

Vec3f sampleUniformSphere(Vec2f u) {
    float z = 1 - 2 * u.x;
    float r = safeSqrt(1 - z * z);
    float phi = 2 * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

Vec3f sampleUniformCone(Vec2f u, float cosThetaMax) {
    float cosTheta = (1 - u.x) + u.x * cosThetaMax;
    float sinTheta = safeSqrt(1 - cosTheta * cosTheta);
    float phi = 2 * kPi * u.y;
    return {std::cos(phi) * sinTheta, std::sin(phi) * sinTheta, cosTheta};
}

Vec2f sampleUniformTriangle(Vec2f u) {
    float b0, b1;
    if (u.x < u.y) {
        b0 = u.x / 2;
        b1 = u.y - b0;
    } else {
        b1 = u.y / 2;
        b0 = u.x - b1;
    }
    return {b0, b1};
}

float sampleTent(float u) {
    // Inverse CDF of the tent on [-1, 1], one half at a time.
    if (u < 0.5f) return -1 + std::sqrt(2 * u);
    return 1 - std::sqrt(2 - 2 * u);
}

Distribution1D::Distribution1D(std::span<const float> weights) {
    pmf_.resize(weights.size());
    cdf_.assign(weights.size() + 1, 0.0);
    for (size_t i = 0; i < weights.size(); ++i) {
        double w = (std::isfinite(weights[i]) && weights[i] > 0) ? weights[i] : 0.0;
        cdf_[i + 1] = cdf_[i] + w;
    }
    total_ = cdf_.back();
    if (total_ <= 0) return;
    for (size_t i = 0; i < weights.size(); ++i) {
        pmf_[i] = float((cdf_[i + 1] - cdf_[i]) / total_);
        cdf_[i] /= total_;
    }
    cdf_.back() = 1.0;
}

uint32_t Distribution1D::sample(float u, float* uRemapped) const {
    // Largest i with cdf_[i] <= u, skipping zero-probability entries.
    auto it = std::upper_bound(cdf_.begin(), cdf_.end(), double(u));
    size_t i = size_t(std::max<ptrdiff_t>(0, (it - cdf_.begin()) - 1));
    i = std::min(i, pmf_.size() - 1);
    while (pmf_[i] == 0 && i > 0) --i;
    while (pmf_[i] == 0 && i + 1 < pmf_.size()) ++i;
    if (uRemapped) {
        double width = cdf_[i + 1] - cdf_[i];
        double rem = width > 0 ? (double(u) - cdf_[i]) / width : 0.0;
        *uRemapped = float(std::clamp(rem, 0.0, 0x1.fffffep-1));
    }
    return uint32_t(i);
}

}  // namespace partita
