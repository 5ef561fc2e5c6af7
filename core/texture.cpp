#include "texture.h"

#include <cmath>

namespace partita {

namespace {
/// The value of alpha byte b: b / 255, computed as the loader computes 8-bit values.
float alphaOf8(uint8_t b) { return float(b) * (1.f / 255.f); }

/// i mod n in [0, n), with one integer division.
int positiveModulo(int i, int n) {
    int m = i % n;
    return m < 0 ? m + n : m;
}

int wrapIndex(int i, int n, WrapMode mode) {
    switch (mode) {
        case WrapMode::ClampToEdge:
            return clamp(i, 0, n - 1);
        case WrapMode::MirroredRepeat: {
            int period = 2 * n;
            int m = positiveModulo(i, period);
            return m < n ? m : period - 1 - m;
        }
        case WrapMode::Repeat:
        default:
            return positiveModulo(i, n);
    }
}

/// The two texel indices a bilinear lookup blends along one axis, i and i + 1, wrapped. The
/// second follows from the first without another division, except where mirroring turns.
void wrapPair(int i, int n, WrapMode mode, int& first, int& second) {
    first = wrapIndex(i, n, mode);
    if (mode == WrapMode::Repeat)
        second = first + 1 == n ? 0 : first + 1;
    else
        second = wrapIndex(i + 1, n, mode);
}
}  // namespace

Vec2f TextureRef::transformUv(Vec2f uv) const {
    if (!hasTransform) return uv;
    float c = std::cos(rotation), s = std::sin(rotation);
    float x = uv.x * scale.x, y = uv.y * scale.y;
    // glTF's rotation matrix is [c s; -s c] applied to (x, y).
    return {c * x + s * y + offset.x, -s * x + c * y + offset.y};
}

Rgba Texture::texel(int x, int y) const {
    const size_t at = (size_t(y) * width + x) * 4;
    if (!rgba8.empty()) {
        const uint8_t* p = &rgba8[at];
        return Rgba{{colorOf8[p[0]], colorOf8[p[1]], colorOf8[p[2]]}, alphaOf8(p[3])};
    }
    const float* p = &rgba[at];
    return Rgba{{p[0], p[1], p[2]}, p[3]};
}

Rgba Texture::lookup(Vec2f uv) const {
    if (width <= 0 || height <= 0) return {};
    auto wrapped = [&](int x, int y) {
        return texel(wrapIndex(x, width, wrapS), wrapIndex(y, height, wrapT));
    };
    float fx = uv.x * width - 0.5f, fy = uv.y * height - 0.5f;
    if (!std::isfinite(fx) || !std::isfinite(fy)) return texel(0, 0);
    // Keep the integer conversion in range for huge coordinates (repeat is periodic anyway); for
    // the usual ones fmod would return its argument unchanged.
    const float rangeX = float(width) * 1024.f, rangeY = float(height) * 1024.f;
    if (std::abs(fx) >= rangeX) fx = std::fmod(fx, rangeX);
    if (std::abs(fy) >= rangeY) fy = std::fmod(fy, rangeY);
    if (filter == TextureFilter::Nearest)
        return wrapped(int(std::floor(fx + 0.5f)), int(std::floor(fy + 0.5f)));
    int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
    float tx = fx - x0, ty = fy - y0;
    int xa, xb, ya, yb;
    wrapPair(x0, width, wrapS, xa, xb);
    wrapPair(y0, height, wrapT, ya, yb);
    Rgba a = texel(xa, ya), b = texel(xb, ya), c = texel(xa, yb), d = texel(xb, yb);
    auto lerp = [](float t, float u, float v) { return u + t * (v - u); };
    Rgba out;
    for (int k = 0; k < 3; ++k)
        out.rgb[k] = lerp(ty, lerp(tx, a.rgb[k], b.rgb[k]), lerp(tx, c.rgb[k], d.rgb[k]));
    out.a = lerp(ty, lerp(tx, a.a, b.a), lerp(tx, c.a, d.a));
    return out;
}

}  // namespace partita
