#include "guide/denoise.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <utility>

#include "thread_pool.h"

namespace partita {

namespace {

constexpr uint32_t kInvalid = std::numeric_limits<uint32_t>::max();

/// What the edge-stopping weights read of the texels, one array per component (so that a row's
/// weights for one tap offset are computed in one vectorisable loop): `region` numbers the
/// pairs (surface, specular vertices) densely, kInvalid for an invalid texel.
struct Guides {
    std::vector<float> px, py, pz, nx, ny, nz, albedo;
    std::vector<uint32_t> region;
};

Guides guidesOf(const GBuffer& gbuffer) {
    const std::vector<GBufferTexel>& texels = gbuffer.texels();
    size_t count = texels.size();
    Guides g;
    for (auto* v : {&g.px, &g.py, &g.pz, &g.nx, &g.ny, &g.nz, &g.albedo}) v->resize(count);
    g.region.resize(count);
    std::map<std::pair<uint32_t, uint8_t>, uint32_t> regions;
    std::pair<uint32_t, uint8_t> last{0, 0};
    uint32_t lastRegion = kInvalid;
    for (size_t i = 0; i < count; ++i) {
        const GBufferTexel& t = texels[i];
        uint32_t region = kInvalid;
        if (t.valid) {
            std::pair<uint32_t, uint8_t> key{t.surface, t.specularVertices};
            if (lastRegion == kInvalid || key != last) {
                auto it = regions.emplace(key, uint32_t(regions.size())).first;
                last = key;
                lastRegion = it->second;
            }
            region = lastRegion;
        }
        g.px[i] = t.position.x;
        g.py[i] = t.position.y;
        g.pz[i] = t.position.z;
        g.nx[i] = t.normal.x;
        g.ny[i] = t.normal.y;
        g.nz[i] = t.normal.z;
        g.albedo[i] = t.albedo;
        g.region[i] = region;
    }
    return g;
}

/// 1 / sigma^2, or 0 (the term switched off) for sigma <= 0.
float inverseSquare(float sigma) { return sigma > 0 ? 1.0f / (sigma * sigma) : 0.0f; }

/// exp(-e) for e >= 0 to ~2e-7 relative (2^x as 2^k 2^f, k the nearest integer, 2^f on
/// [-1/2, 1/2] by its Taylor polynomial of degree 6), 0 for e >= 80: branch-free, so that a
/// row of weights vectorises, and a pure function of e, so the output does not depend on
/// threads.
inline float expNegative(float e) {
    float clamped = std::min(e, 80.0f);
    float x = -clamped * 1.44269504f;  // log2(e) * -e, in [-116, 0]
    float k = std::floor(x + 0.5f);
    float f = x - k;  // in [-1/2, 1/2]
    // 2^f = sum (f ln 2)^i / i!.
    float p = 1.5403530e-4f;
    p = p * f + 1.3333558e-3f;
    p = p * f + 9.6181291e-3f;
    p = p * f + 5.5504109e-2f;
    p = p * f + 2.4022651e-1f;
    p = p * f + 6.9314718e-1f;
    p = p * f + 1.0f;
    int32_t bits = (int32_t(k) + 127) << 23;  // 2^k, k >= -116: a normal float
    float scale;
    std::memcpy(&scale, &bits, sizeof scale);
    return e < 80 ? p * scale : 0.0f;
}

/// The 3x3 kernel (1/4, 1/2, 1/4) in each direction; the eight outer taps.
constexpr float kKernel[3] = {0.25f, 0.5f, 0.25f};
constexpr int kTaps = 8;

struct Level {
    const Guides& g;
    int width, height, channels, step;
    float invNormal, invAlbedo, invPosition;
    const float* in;
    float* out;

    /// weights[x] = the kernel's h times the edge-stopping factor of the tap (x + dx, yy) for
    /// pixel (x, y), 0 off the image, on another region or an invalid texel.
    void tapWeights(int y, int yy, int dx, float h, float* __restrict weights) const {
        std::fill(weights, weights + width, 0.0f);
        if (yy < 0 || yy >= height) return;
        const int begin = std::max(0, -dx), end = std::min(width, width - dx);
        if (end <= begin) return;
        // Pointers to the first pixel p = (begin, y) and its tap q = (begin + dx, yy), both in
        // the image: a pointer to before a row's start is undefined even if never read (found
        // by make test-asan's UBSan: y * width + dx wrapped for dx < 0 at yy = 0).
        const size_t rowP = size_t(y) * size_t(width) + size_t(begin);
        const size_t rowQ = size_t(yy) * size_t(width) + size_t(begin + dx);
        const float *px = g.px.data() + rowP, *py = g.py.data() + rowP, *pz = g.pz.data() + rowP;
        const float *nx = g.nx.data() + rowP, *ny = g.ny.data() + rowP, *nz = g.nz.data() + rowP;
        const float *ap = g.albedo.data() + rowP, *aq = g.albedo.data() + rowQ;
        const float *qx = g.px.data() + rowQ, *qy = g.py.data() + rowQ, *qz = g.pz.data() + rowQ;
        const float *mx = g.nx.data() + rowQ, *my = g.ny.data() + rowQ, *mz = g.nz.data() + rowQ;
        const uint32_t *rp = g.region.data() + rowP, *rq = g.region.data() + rowQ;
        float* w = weights + begin;
        for (int x = 0; x < end - begin; ++x) {
            float dnx = nx[x] - mx[x], dny = ny[x] - my[x], dnz = nz[x] - mz[x];
            float da = ap[x] - aq[x];
            float dpx = qx[x] - px[x], dpy = qy[x] - py[x], dpz = qz[x] - pz[x];
            float dist2 = dpx * dpx + dpy * dpy + dpz * dpz;
            float plane = nx[x] * dpx + ny[x] * dpy + nz[x] * dpz;
            float e = (dnx * dnx + dny * dny + dnz * dnz) * invNormal + da * da * invAlbedo +
                      plane * plane / std::max(dist2, 1e-30f) * invPosition;
            bool same = rp[x] == rq[x] && rp[x] != kInvalid;
            w[x] = same ? h * expNegative(e) : 0.0f;
        }
    }

    /// Row y of the level; `scratch` holds kTaps * width floats.
    void row(int y, float* scratch) const {
        const float* taps[kTaps];
        int offsets[kTaps], t = 0;
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) {
                if (i == 1 && j == 1) continue;
                int dx = (i - 1) * step, dy = (j - 1) * step;
                tapWeights(y, y + dy, dx, kKernel[i] * kKernel[j], scratch + size_t(t) * width);
                taps[t] = scratch + size_t(t) * width;
                offsets[t++] = dy * width + dx;
            }
        size_t n = size_t(channels);
        for (int x = 0; x < width; ++x) {
            size_t p = size_t(y) * size_t(width) + size_t(x);
            const float* inP = in + p * n;
            float* outP = out + p * n;
            if (g.region[p] == kInvalid) {
                std::copy(inP, inP + n, outP);
                continue;
            }
            // The taps with weight, normalised with the centre's (whose difference is 0).
            float weights[kTaps];
            const float* values[kTaps];
            int count = 0;
            float sum = kKernel[1] * kKernel[1];
            for (int k = 0; k < kTaps; ++k) {
                float w = taps[k][x];
                if (!(w > 0)) continue;
                sum += w;
                weights[count] = w;
                values[count++] = in + (ptrdiff_t(p) + offsets[k]) * ptrdiff_t(n);
            }
            float inv = 1.0f / sum;
            for (int k = 0; k < count; ++k) weights[k] *= inv;
            // out = in + sum_k w_k (in_k - in), tap by tap over the contiguous channels.
            std::copy(inP, inP + n, outP);
            for (int k = 0; k < count; ++k) {
                const float* v = values[k];
                float w = weights[k];
                for (size_t c = 0; c < n; ++c) outP[c] += w * (v[c] - inP[c]);
            }
        }
    }
};

}  // namespace

std::vector<std::vector<float>> denoisePartitions(const GBuffer& gbuffer,
                                                  const std::vector<std::vector<float>>& images,
                                                  const DenoiseSettings& settings,
                                                  ThreadPool* pool) {
    int width = gbuffer.width(), height = gbuffer.height();
    size_t pixels = size_t(width) * size_t(height), n = images.size();
    for (const std::vector<float>& image : images)
        if (image.size() != pixels)
            throw std::invalid_argument("denoisePartitions: an image's size is not the G-buffer's");
    if (n == 0 || pixels == 0 || settings.levels <= 0) return images;

    Guides guides = guidesOf(gbuffer);
    // Channels interleaved per pixel: one tap's weight then meets all partitions' values in one
    // contiguous run.
    // (b is written in full by the first level before it is read: left uninitialised.)
    std::unique_ptr<float[]> a(new float[pixels * n]), b(new float[pixels * n]);
    for (size_t c = 0; c < n; ++c)
        for (size_t p = 0; p < pixels; ++p) a[p * n + c] = images[c][p];
    for (int l = 0; l < settings.levels; ++l) {
        Level level{guides,
                    width,
                    height,
                    int(n),
                    1 << std::min(l, 30),
                    inverseSquare(settings.normalSigma),
                    inverseSquare(settings.albedoSigma),
                    inverseSquare(settings.positionSigma),
                    a.get(),
                    b.get()};
        auto rowBody = [&](size_t y) {
            std::vector<float> scratch(size_t(kTaps) * size_t(width));
            level.row(int(y), scratch.data());
        };
        if (pool)
            pool->parallelFor(size_t(height), rowBody);
        else
            for (int y = 0; y < height; ++y) rowBody(size_t(y));
        a.swap(b);
    }
    std::vector<std::vector<float>> out(n, std::vector<float>(pixels));
    for (size_t c = 0; c < n; ++c)
        for (size_t p = 0; p < pixels; ++p) out[c][p] = a[p * n + c];
    return out;
}

}  // namespace partita
