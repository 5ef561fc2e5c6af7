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

}  // namespace partita
