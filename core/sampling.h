// Warping functions from the unit square to common domains, with their densities, plus a
// piecewise-constant 1D distribution for discrete choices (lights, triangles).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "math/vec.h"

namespace partita {

/// Cosine-weighted hemisphere around +z (Malley's method); pdf = cos(theta) / pi.
Vec3f sampleCosineHemisphere(Vec2f u);
inline float cosineHemispherePdf(float cosTheta) { return cosTheta > 0 ? cosTheta * kInvPi : 0; }

Vec3f sampleUniformSphere(Vec2f u);
constexpr float uniformSpherePdf() { return 1.0f / (4.0f * kPi); }

/// Uniform directions in the cone around +z with cos(theta) >= cosThetaMax.
Vec3f sampleUniformCone(Vec2f u, float cosThetaMax);
inline float uniformConePdf(float cosThetaMax) { return 1.0f / (2.0f * kPi * (1.0f - cosThetaMax)); }

/// Concentric mapping of the square to the unit disk (Shirley & Chiu 1997).
Vec2f sampleConcentricDisk(Vec2f u);

/// Uniform barycentrics (b0, b1) on a triangle; b2 = 1 - b0 - b1 (Heitz 2019, low distortion).
Vec2f sampleUniformTriangle(Vec2f u);

/// Tent filter of radius 1 sampled exactly: returns an offset in [-1, 1] with density 1 - |x|.
float sampleTent(float u);

/// Veach's power heuristic with beta = 2, written for two strategies.
inline float powerHeuristic(float pdfA, float pdfB) {
    float a = pdfA * pdfA, b = pdfB * pdfB;
    if (std::isinf(a)) return 1.0f;
    return a + b > 0 ? a / (a + b) : 0.0f;
}

/// Discrete distribution proportional to non-negative weights.
class Distribution1D {
public:
    Distribution1D() = default;
    explicit Distribution1D(std::span<const float> weights);

    size_t size() const { return pmf_.size(); }
    bool empty() const { return pmf_.empty() || total_ <= 0; }
    double total() const { return total_; }
    /// Index i chosen with probability pmf(i). `u` in [0, 1); `uRemapped` (optional) receives a
    /// fresh uniform variate recovered from the leftover of u.
    uint32_t sample(float u, float* uRemapped = nullptr) const;
    float pmf(uint32_t i) const { return pmf_[i]; }

private:
    std::vector<float> pmf_;
    std::vector<double> cdf_;  // cdf_[i] = sum of pmf over [0, i); size + 1 entries
    double total_ = 0;
};

}  // namespace partita
