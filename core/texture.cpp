#include "texture.h"

#include <cmath>

namespace partita {

namespace {
int wrapIndex(int i, int n, WrapMode mode) {
    switch (mode) {
        case WrapMode::ClampToEdge:
            return clamp(i, 0, n - 1);
        case WrapMode::MirroredRepeat: {
            int period = 2 * n;
            int m = ((i % period) + period) % period;
            return m < n ? m : period - 1 - m;
        }
        case WrapMode::Repeat:
        default:
            return ((i % n) + n) % n;
    }
}
}  // namespace

Vec2f TextureRef::transformUv(Vec2f uv) const {
    if (!hasTransform) return uv;
    float c = std::cos(rotation), s = std::sin(rotation);
    float x = uv.x * scale.x, y = uv.y * scale.y;
    // glTF's rotation matrix is [c s; -s c] applied to (x, y).
    return {c * x + s * y + offset.x, -s * x + c * y + offset.y};
}

Rgba Texture::lookup(Vec2f uv) const {
    if (width <= 0 || height <= 0) return {};
    auto texel = [&](int x, int y) {
        x = wrapIndex(x, width, wrapS);
        y = wrapIndex(y, height, wrapT);
        const float* p = &rgba[(size_t(y) * width + x) * 4];
        return Rgba{{p[0], p[1], p[2]}, p[3]};
    };
    float fx = uv.x * width - 0.5f, fy = uv.y * height - 0.5f;
    if (!std::isfinite(fx) || !std::isfinite(fy)) return texel(0, 0);
    // Keep the integer conversion in range for huge coordinates (repeat is periodic anyway).
    fx = std::fmod(fx, float(width) * 1024.f);
    fy = std::fmod(fy, float(height) * 1024.f);
    if (filter == TextureFilter::Nearest)
        return texel(int(std::floor(fx + 0.5f)), int(std::floor(fy + 0.5f)));
    int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
    float tx = fx - x0, ty = fy - y0;
    Rgba a = texel(x0, y0), b = texel(x0 + 1, y0), c = texel(x0, y0 + 1), d = texel(x0 + 1, y0 + 1);
    auto lerp = [](float t, float u, float v) { return u + t * (v - u); };
    Rgba out;
    for (int k = 0; k < 3; ++k)
        out.rgb[k] = lerp(ty, lerp(tx, a.rgb[k], b.rgb[k]), lerp(tx, c.rgb[k], d.rgb[k]));
    out.a = lerp(ty, lerp(tx, a.a, b.a), lerp(tx, c.a, d.a));
    return out;
}

}  // namespace partita
