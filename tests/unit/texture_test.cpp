// Texture lookups against a reference written out texel by texel: bilinear and nearest
// filtering under every wrap mode, for coordinates inside, around and far outside [0, 1].
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "rng.h"
#include "texture.h"

namespace partita {
namespace {

Texture randomTexture(int width, int height, WrapMode s, WrapMode t, TextureFilter filter) {
    Texture tex;
    tex.width = width;
    tex.height = height;
    tex.wrapS = s;
    tex.wrapT = t;
    tex.filter = filter;
    Rng rng(7, uint64_t(width * 100 + height));
    tex.rgba.resize(size_t(width) * height * 4);
    for (float& v : tex.rgba) v = rng.nextFloat();
    return tex;
}

/// glTF's wrap of texel index i into [0, n), the sampler rules spelled out with floor division.
int referenceWrap(int i, int n, WrapMode mode) {
    auto floorMod = [](int a, int m) { return a - m * int(std::floor(double(a) / m)); };
    switch (mode) {
        case WrapMode::ClampToEdge:
            return std::min(std::max(i, 0), n - 1);
        case WrapMode::MirroredRepeat: {
            int m = floorMod(i, 2 * n);  // one period: the image, then its mirror image
            return m < n ? m : 2 * n - 1 - m;
        }
        default:
            return floorMod(i, n);
    }
}

Rgba referenceLookup(const Texture& t, Vec2f uv) {
    auto texel = [&](int x, int y) {
        x = referenceWrap(x, t.width, t.wrapS);
        y = referenceWrap(y, t.height, t.wrapT);
        const float* p = &t.rgba[(size_t(y) * t.width + x) * 4];
        return Rgba{{p[0], p[1], p[2]}, p[3]};
    };
    float fx = uv.x * t.width - 0.5f, fy = uv.y * t.height - 0.5f;
    if (t.filter == TextureFilter::Nearest)
        return texel(int(std::floor(fx + 0.5f)), int(std::floor(fy + 0.5f)));
    int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
    float tx = fx - x0, ty = fy - y0;
    Rgba a = texel(x0, y0), b = texel(x0 + 1, y0), c = texel(x0, y0 + 1), d = texel(x0 + 1, y0 + 1);
    auto lerp = [](float w, float u, float v) { return u + w * (v - u); };
    Rgba out;
    for (int k = 0; k < 3; ++k)
        out.rgb[k] = lerp(ty, lerp(tx, a.rgb[k], b.rgb[k]), lerp(tx, c.rgb[k], d.rgb[k]));
    out.a = lerp(ty, lerp(tx, a.a, b.a), lerp(tx, c.a, d.a));
    return out;
}

TEST(Texture, LookupMatchesTheTexelByTexelReferenceForEveryWrapModeAndFilter) {
    const WrapMode modes[] = {WrapMode::Repeat, WrapMode::MirroredRepeat, WrapMode::ClampToEdge};
    // Texel centres, texel edges (where wrapping turns), and coordinates up to 40 periods out.
    std::vector<float> coordinates;
    for (int k = -200; k <= 200; ++k) coordinates.push_back(float(k) / 10.0f);
    Rng rng(3, 3);
    for (int k = 0; k < 400; ++k) coordinates.push_back(80.0f * rng.nextFloat() - 40.0f);
    int compared = 0;
    for (WrapMode s : modes)
        for (WrapMode t : modes)
            for (TextureFilter filter : {TextureFilter::Linear, TextureFilter::Nearest}) {
                Texture tex = randomTexture(5, 3, s, t, filter);
                for (size_t i = 0; i < coordinates.size(); ++i) {
                    Vec2f uv{coordinates[i], coordinates[coordinates.size() - 1 - i]};
                    Rgba got = tex.lookup(uv), want = referenceLookup(tex, uv);
                    ASSERT_EQ(got.rgb, want.rgb) << "uv " << uv.x << ", " << uv.y;
                    ASSERT_EQ(got.a, want.a) << "uv " << uv.x << ", " << uv.y;
                    ++compared;
                }
            }
    EXPECT_EQ(compared, 3 * 3 * 2 * 801);
}

TEST(Texture, HugeAndNonFiniteCoordinatesStayInsideTheImage) {
    // Texels in [0.25, 0.75]: a blend of texels stays in that range, while memory read from
    // outside the image (or a garbage conversion of a huge coordinate) would not.
    Texture tex =
        randomTexture(4, 4, WrapMode::Repeat, WrapMode::MirroredRepeat, TextureFilter::Linear);
    for (float& v : tex.rgba) v = 0.25f + 0.5f * v;
    for (Vec2f uv : {Vec2f{1e9f, -1e9f}, Vec2f{-3e30f, 2e20f}, Vec2f{4096.3f, -8192.7f}}) {
        Rgba v = tex.lookup(uv);
        for (int k = 0; k < 3; ++k) {
            EXPECT_GE(v.rgb[k], 0.25f) << uv.x << ", " << uv.y;
            EXPECT_LE(v.rgb[k], 0.75f) << uv.x << ", " << uv.y;
        }
    }
    // A coordinate that is not finite reads the first texel.
    const float inf = std::numeric_limits<float>::infinity();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (Vec2f uv : {Vec2f{inf, 0.5f}, Vec2f{0.5f, nan}, Vec2f{-inf, inf}}) {
        Rgba v = tex.lookup(uv), first = tex.texel(0, 0);
        EXPECT_EQ(v.rgb, first.rgb);
        EXPECT_EQ(v.a, first.a);
    }
}

}  // namespace
}  // namespace partita
