#include "sampling.h"

#include <algorithm>
#include <cmath>

namespace partita {

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
    // Largest i with cdf_[i] <= u (or 0), skipping zero-probability entries. A branchless binary
    // search (the step is a conditional move): the index drawn is as good as random to a
    // branch predictor. Invariant: the answer lies in [base, base + len).
    const double x = u;
    size_t base = 0, len = cdf_.size();
    while (len > 1) {
        size_t half = len / 2;
        base = cdf_[base + half] <= x ? base + half : base;
        len -= half;
    }
    size_t i = std::min(base, pmf_.size() - 1);
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
