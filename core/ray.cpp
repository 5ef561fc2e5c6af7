#include "ray.h"

#include <bit>
#include <cmath>
#include <cstdint>

namespace partita {

namespace {
constexpr float kOrigin = 1.0f / 32.0f;
constexpr float kFloatScale = 1.0f / 65536.0f;
constexpr float kIntScale = 256.0f;

float offsetComponent(float p, float n) {
    int32_t ofi = int32_t(kIntScale * n);
    int32_t bits = std::bit_cast<int32_t>(p);
    float pi = std::bit_cast<float>(bits + (p < 0 ? -ofi : ofi));
    return std::abs(p) < kOrigin ? p + kFloatScale * n : pi;
}
}  // namespace

Vec3f offsetRayOrigin(Vec3f p, Vec3f ng, Vec3f w) {
    Vec3f n = dot(ng, w) < 0 ? -ng : ng;
    return {offsetComponent(p.x, n.x), offsetComponent(p.y, n.y), offsetComponent(p.z, n.z)};
}

Ray spawnShadowRay(Vec3f p, Vec3f ngP, Vec3f q, Vec3f ngQ) {
    Vec3f from = offsetRayOrigin(p, ngP, q - p);
    Vec3f to = offsetRayOrigin(q, ngQ, p - q);
    return {from, to - from, 1.0f - 1e-4f};
}

}  // namespace partita
