// Small fixed-size vector types used throughout the renderer. Float precision everywhere: Embree
// works in float, and the film accumulates in float per pixel per pass.
#pragma once

#include <algorithm>
#include <cmath>

namespace partita {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 0.31830988618379067154f;
constexpr float kInf = INFINITY;

struct Vec2f {
    float x = 0, y = 0;
    constexpr Vec2f() = default;
    constexpr Vec2f(float x_, float y_) : x(x_), y(y_) {}
    constexpr Vec2f operator+(Vec2f o) const { return {x + o.x, y + o.y}; }
    constexpr Vec2f operator-(Vec2f o) const { return {x - o.x, y - o.y}; }
    constexpr Vec2f operator*(float s) const { return {x * s, y * s}; }
    constexpr float operator[](int i) const { return i == 0 ? x : y; }
};

struct Vec3f {
    float x = 0, y = 0, z = 0;
    constexpr Vec3f() = default;
    constexpr explicit Vec3f(float s) : x(s), y(s), z(s) {}
    constexpr Vec3f(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}

    constexpr float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr Vec3f operator-() const { return {-x, -y, -z}; }
    constexpr Vec3f operator+(Vec3f o) const { return {x + o.x, y + o.y, z + o.z}; }
    constexpr Vec3f operator-(Vec3f o) const { return {x - o.x, y - o.y, z - o.z}; }
    constexpr Vec3f operator*(Vec3f o) const { return {x * o.x, y * o.y, z * o.z}; }
    constexpr Vec3f operator/(Vec3f o) const { return {x / o.x, y / o.y, z / o.z}; }
    constexpr Vec3f operator*(float s) const { return {x * s, y * s, z * s}; }
    constexpr Vec3f operator/(float s) const { return {x / s, y / s, z / s}; }
    constexpr Vec3f& operator+=(Vec3f o) { return *this = *this + o; }
    constexpr Vec3f& operator-=(Vec3f o) { return *this = *this - o; }
    constexpr Vec3f& operator*=(Vec3f o) { return *this = *this * o; }
    constexpr Vec3f& operator*=(float s) { return *this = *this * s; }
    constexpr Vec3f& operator/=(float s) { return *this = *this / s; }
    constexpr bool operator==(const Vec3f&) const = default;
};

constexpr Vec3f operator*(float s, Vec3f v) { return v * s; }
constexpr float dot(Vec3f a, Vec3f b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr float absDot(Vec3f a, Vec3f b) {
    float d = dot(a, b);
    return d < 0 ? -d : d;
}
constexpr Vec3f cross(Vec3f a, Vec3f b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float lengthSquared(Vec3f v) { return dot(v, v); }
inline float length(Vec3f v) { return std::sqrt(dot(v, v)); }
inline Vec3f normalize(Vec3f v) { return v / length(v); }
inline Vec3f min(Vec3f a, Vec3f b) {
    return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
inline Vec3f max(Vec3f a, Vec3f b) {
    return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
inline float maxComponent(Vec3f v) { return std::max(v.x, std::max(v.y, v.z)); }
inline bool isFinite(Vec3f v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
inline bool isBlack(Vec3f v) { return v.x == 0 && v.y == 0 && v.z == 0; }
/// Flip `v` into the hemisphere of `ref`.
inline Vec3f faceForward(Vec3f v, Vec3f ref) { return dot(v, ref) < 0 ? -v : v; }

/// Linear RGB radiance / reflectance. Same layout as Vec3f; the alias documents intent.
using Rgb = Vec3f;

/// Rec. 709 luminance, the scalar f* that MCMC targets (paper Section 3).
inline float luminance(Rgb c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

template <typename T>
constexpr T clamp(T v, T lo, T hi) {
    return v < lo ? lo : (v > hi ? hi : v);
}
inline float safeSqrt(float v) { return std::sqrt(std::max(0.f, v)); }
inline float sqr(float v) { return v * v; }

}  // namespace partita
