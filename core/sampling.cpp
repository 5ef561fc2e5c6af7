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

}  // namespace partita
