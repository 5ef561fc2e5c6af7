// The interaction type of a light path in Heckbert's notation, the key of a partition
// (paper Section 4.1). A path x0 (eye) .. xM (light) has M-1 scattering vertices, each S when
// its BSDF is a Dirac delta and D otherwise. The string is written light-to-eye: a path that
// leaves the light, hits a mirror, then a diffuse wall, then the eye is "LSDE".
#pragma once

#include <compare>
#include <cstdint>
#include <functional>
#include <string>

namespace partita {

class PathType {
  public:
    static constexpr int kMaxScatteringVertices = 64;

    PathType() = default;

    /// Append the next scattering vertex on the camera side (x1, then x2, ...).
    PathType withVertex(bool specular) const {
        PathType t = *this;
        if (t.count_ < kMaxScatteringVertices) {
            if (specular) t.specularMask_ |= (uint64_t(1) << t.count_);
            ++t.count_;
        }
        return t;
    }

    int scatteringVertices() const { return count_; }
    /// Whether scattering vertex x_{i+1} (camera order, 0-based i) is specular.
    bool isSpecular(int i) const { return (specularMask_ >> i) & 1u; }

    /// Heckbert string, light to eye, e.g. "LDSDE".
    std::string toString() const {
        std::string s = "L";
        for (int i = count_ - 1; i >= 0; --i) s += isSpecular(i) ? 'S' : 'D';
        s += 'E';
        return s;
    }

    /// Inverse of toString; returns false for anything that is not L[DS]*E.
    static bool parse(const std::string& text, PathType& out);
    /// The type of `count` scattering vertices with specularMask() `mask` (serialised types);
    /// false when the count is out of range or the mask has bits at or above it.
    static bool fromBits(uint64_t mask, int count, PathType& out) {
        if (count < 0 || count > kMaxScatteringVertices || (count < 64 && (mask >> count) != 0))
            return false;
        PathType t;
        for (int i = 0; i < count; ++i) t = t.withVertex((mask >> i) & 1u);
        out = t;
        return true;
    }

    uint64_t specularMask() const { return specularMask_; }
    auto operator<=>(const PathType&) const = default;

  private:
    uint64_t specularMask_ = 0;
    uint16_t count_ = 0;
};

inline bool PathType::parse(const std::string& text, PathType& out) {
    if (text.size() < 2 || text.front() != 'L' || text.back() != 'E') return false;
    if (text.size() - 2 > size_t(kMaxScatteringVertices)) return false;
    PathType t;
    // The string runs light-to-eye; vertices are appended camera-first.
    for (size_t i = text.size() - 2; i >= 1; --i) {
        char c = text[i];
        if (c != 'S' && c != 'D') return false;
        t = t.withVertex(c == 'S');
    }
    out = t;
    return true;
}

/// Whether paths of type `t` belong to the direct-light class: every scattering vertex but the
/// one next to the light is specular (L E, L S+ E, L D E, L D S+ E). mlt estimates this class per
/// pixel by default (integrators/mlt/direct_light.h), and so do partitioned and guided when they
/// choose their estimators (partition/partition.h).
inline bool isDirectLightType(const PathType& t) {
    // Camera order: vertex i = 0 is x1 (next to the eye), count - 1 the one next to the light.
    for (int i = 0; i + 1 < t.scatteringVertices(); ++i)
        if (!t.isSpecular(i)) return false;
    return true;
}

}  // namespace partita

template <>
struct std::hash<partita::PathType> {
    size_t operator()(const partita::PathType& t) const noexcept {
        return std::hash<uint64_t>()(t.specularMask() * 0x9e3779b97f4a7c15ull +
                                     t.scatteringVertices());
    }
};
