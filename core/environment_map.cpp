#include "environment_map.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace partita {

namespace {

/// Inverts a cumulative table over n bins at u in [0, 1): the bin and the position within it.
int invertCdf(const float* cdf, int n, float u, float& within) {
    float target = u * cdf[n];
    // The first bin whose end passes the target; empty bins cannot be chosen.
    const float* end = std::upper_bound(cdf + 1, cdf + n + 1, target);
    int bin = std::clamp(int(end - cdf) - 1, 0, n - 1);
    while (bin > 0 && cdf[bin + 1] - cdf[bin] <= 0) --bin;
    float width = cdf[bin + 1] - cdf[bin];
    within = width > 0 ? std::clamp((target - cdf[bin]) / width, 0.0f, 0x1.fffffep-1f) : 0.5f;
    return bin;
}

}  // namespace

EnvironmentMap::EnvironmentMap(Image radiance, float rotationDegrees)
    : image_(std::move(radiance)) {
    if (image_.width < 1 || image_.height < 1)
        throw std::invalid_argument("environment map: empty image");
    float rot = rotationDegrees * kPi / 180;
    cosRot_ = std::cos(rot);
    sinRot_ = std::sin(rot);
    int w = image_.width, h = image_.height;
    rowCdf_.assign(size_t(h) + 1, 0);
    columnCdf_.assign(size_t(h) * (w + 1), 0);
    pixelPmf_.assign(size_t(w) * h, 0);
    double total = 0, sphereIntegral = 0;
    for (int y = 0; y < h; ++y) {
        float sinTheta = std::sin(kPi * (float(y) + 0.5f) / float(h));
        float* cdf = &columnCdf_[size_t(y) * (w + 1)];
        for (int x = 0; x < w; ++x) {
            float lum = std::max(0.0f, luminance(image_.at(x, y)));
            if (!std::isfinite(lum)) lum = 0;
            cdf[x + 1] = cdf[x] + lum * sinTheta;
            sphereIntegral += double(lum) * sinTheta;
        }
        rowCdf_[size_t(y) + 1] = rowCdf_[size_t(y)] + cdf[w];
        total += cdf[w];
    }
    for (int y = 0; y < h && total > 0; ++y) {
        const float* cdf = &columnCdf_[size_t(y) * (w + 1)];
        for (int x = 0; x < w; ++x)
            pixelPmf_[size_t(y) * w + x] = float((cdf[x + 1] - cdf[x]) / total);
    }
    // Mean over the sphere: sum of L sin(theta) dtheta dphi / (4 pi).
    meanLuminance_ = float(sphereIntegral * (kPi / h) * (2 * kPi / w) / (4 * kPi));
}

EnvironmentMap EnvironmentMap::uniform(Rgb radiance) {
    Image img(64, 32);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 64; ++x) img.set(x, y, radiance);
    return EnvironmentMap(std::move(img));
}

Vec2f EnvironmentMap::uvOf(Vec3f d) const {
    // Undo the map's rotation about +Y.
    Vec3f r{cosRot_ * d.x - sinRot_ * d.z, d.y, sinRot_ * d.x + cosRot_ * d.z};
    float u = 0.5f + std::atan2(r.x, -r.z) / (2 * kPi);
    float v = std::acos(std::clamp(r.y, -1.0f, 1.0f)) / kPi;
    return {u - std::floor(u), v};
}

Vec3f EnvironmentMap::directionOf(Vec2f uv) const {
    float theta = uv.y * kPi, phi = (uv.x - 0.5f) * 2 * kPi;
    float sinTheta = std::sin(theta);
    Vec3f r{sinTheta * std::sin(phi), std::cos(theta), -sinTheta * std::cos(phi)};
    // Apply the rotation (the inverse of uvOf's).
    return {cosRot_ * r.x + sinRot_ * r.z, r.y, -sinRot_ * r.x + cosRot_ * r.z};
}

int EnvironmentMap::pixelIndex(Vec2f uv) const {
    int x = std::clamp(int(uv.x * float(image_.width)), 0, image_.width - 1);
    int y = std::clamp(int(uv.y * float(image_.height)), 0, image_.height - 1);
    return y * image_.width + x;
}

Rgb EnvironmentMap::radiance(Vec3f d) const {
    int i = pixelIndex(uvOf(d));
    return image_.at(i % image_.width, i / image_.width);
}

bool EnvironmentMap::sample(Vec2f u, Vec3f& d, float& pdfOut) const {
    if (isBlack()) return false;
    int w = image_.width, h = image_.height;
    float fy, fx;
    int y = invertCdf(rowCdf_.data(), h, u.y, fy);
    int x = invertCdf(&columnCdf_[size_t(y) * (w + 1)], w, u.x, fx);
    Vec2f uv{(float(x) + fx) / float(w), (float(y) + fy) / float(h)};
    d = directionOf(uv);
    // The chosen pixel's density (pdf(d) would look the pixel up again from d, which rounding
    // can move across the pixel's edge).
    float sinTheta = std::sin(uv.y * kPi);
    if (!(sinTheta > 0)) return false;
    pdfOut = pixelPmf_[size_t(y) * w + x] * float(w) * float(h) / (2 * kPi * kPi * sinTheta);
    return pdfOut > 0;
}

float EnvironmentMap::pdf(Vec3f d) const {
    Vec2f uv = uvOf(d);
    float sinTheta = std::sin(uv.y * kPi);
    if (!(sinTheta > 0)) return 0;
    float p = pixelPmf_[size_t(pixelIndex(uv))];
    return p * float(image_.width) * float(image_.height) / (2 * kPi * kPi * sinTheta);
}

}  // namespace partita
