// ImageGuide::candidates: S' (paper Eq. 15) of every candidate Y'(p), the guided move's costly
// part (|Y'| = 128 G-buffer reads for each new pixel; ~25% of a guided render's time when done
// one sPrime call at a time). With AVX2 eight candidates go at a time: their texels' fields
// are gathered from the G-buffer by pixel index, V' from the support mask's bits, and Eq. 15
// is arranged with one division instead of sPrime's square root and two divisions:
//   w = d / |d|, |n.w| cos' / |d|^2 = |n.d| |n'.d| / |d|^4            (a surface anchor)
//                                   = |n.d| / (|d|^2 |d|)             (a point light)
//   and without cos' or |d|^2          |n.d| / |d|                    (an anchor at infinity)
// Every lane runs the same instructions, so a pixel gets the same weight in whichever lane and
// call it is computed: the ratio of Eq. 16 (guided_choice.h) reads S'(q) and S'(p) at single
// offsets and relies on that. Without AVX2 (PARTITA_ARCH=portable) each candidate is sPrime.
#include <algorithm>
#include <cmath>
#include <cstddef>

#include "guide/image_guide.h"

#ifdef __AVX2__
#include <immintrin.h>
#endif

namespace partita {

#ifdef __AVX2__

namespace {

// The G-buffer texel's fields as 32-bit words (gbuffer.h GBufferTexel).
constexpr int kTexelWords = int(sizeof(GBufferTexel) / 4);
static_assert(sizeof(GBufferTexel) % 4 == 0);
static_assert(offsetof(GBufferTexel, position) == 0 && offsetof(GBufferTexel, normal) == 12);
static_assert(offsetof(GBufferTexel, albedo) == 24 && offsetof(GBufferTexel, cameraTerm) == 28);
static_assert(offsetof(GBufferTexel, valid) / 4 == 9, "valid lies in word 9");
constexpr int kValidShift = int(offsetof(GBufferTexel, valid) % 4) * 8;

/// Field `word` (0..kTexelWords-1) of the texels at `index` (pixel indices).
inline __m256 gatherField(const float* texels, __m256i wordIndex, int word) {
    return _mm256_i32gather_ps(texels + word, wordIndex, 4);
}

inline __m256 absolute(__m256 v) { return _mm256_andnot_ps(_mm256_set1_ps(-0.0f), v); }

/// S' of the eight pixels (x, y); 0 off the image.
struct LaneKernel {
    const float* texels;
    const int* maskWords;  // the partition's support bits as 32-bit words
    int width, height;
    __m256 anchorX, anchorY, anchorZ, anchorNX, anchorNY, anchorNZ;
    bool atInfinity, hasNormal;
    float epsilon;

    __m256 operator()(__m256i x, __m256i y) const {
        const __m256i minusOne = _mm256_set1_epi32(-1);
        __m256i onImage = _mm256_and_si256(
            _mm256_and_si256(_mm256_cmpgt_epi32(x, minusOne), _mm256_cmpgt_epi32(y, minusOne)),
            _mm256_and_si256(_mm256_cmpgt_epi32(_mm256_set1_epi32(width), x),
                             _mm256_cmpgt_epi32(_mm256_set1_epi32(height), y)));
        // Off the image: pixel 0 is read (always there) and the lane's weight zeroed below.
        __m256i pixel = _mm256_and_si256(
            _mm256_add_epi32(_mm256_mullo_epi32(y, _mm256_set1_epi32(width)), x), onImage);
        __m256i word = _mm256_mullo_epi32(pixel, _mm256_set1_epi32(kTexelWords));

        __m256i validWord =
            _mm256_i32gather_epi32(reinterpret_cast<const int*>(texels) + 9, word, 4);
        __m256i invalid =
            _mm256_cmpeq_epi32(_mm256_and_si256(validWord, _mm256_set1_epi32(0xff << kValidShift)),
                               _mm256_setzero_si256());
        __m256i keep = _mm256_andnot_si256(invalid, onImage);

        __m256 dx = _mm256_sub_ps(anchorX, gatherField(texels, word, 0));
        __m256 dy = _mm256_sub_ps(anchorY, gatherField(texels, word, 1));
        __m256 dz = _mm256_sub_ps(anchorZ, gatherField(texels, word, 2));
        __m256 dist2 = _mm256_fmadd_ps(dz, dz, _mm256_fmadd_ps(dy, dy, _mm256_mul_ps(dx, dx)));
        __m256 nDotD =
            _mm256_fmadd_ps(gatherField(texels, word, 5), dz,
                            _mm256_fmadd_ps(gatherField(texels, word, 4), dy,
                                            _mm256_mul_ps(gatherField(texels, word, 3), dx)));
        __m256 numerator = absolute(nDotD), denominator;
        if (atInfinity) {
            denominator = _mm256_sqrt_ps(dist2);
        } else if (hasNormal) {
            __m256 anchorCos = _mm256_fmadd_ps(
                anchorNZ, dz, _mm256_fmadd_ps(anchorNY, dy, _mm256_mul_ps(anchorNX, dx)));
            numerator = _mm256_mul_ps(numerator, absolute(anchorCos));
            denominator = _mm256_mul_ps(dist2, dist2);
        } else {
            denominator = _mm256_mul_ps(dist2, _mm256_sqrt_ps(dist2));
        }
        __m256 geometry = _mm256_div_ps(numerator, denominator);

        // V' from bit (pixel) of the mask: word pixel / 32, bit pixel % 32.
        __m256i bits = _mm256_i32gather_epi32(maskWords, _mm256_srli_epi32(pixel, 5), 4);
        __m256i bit = _mm256_and_si256(
            _mm256_srlv_epi32(bits, _mm256_and_si256(pixel, _mm256_set1_epi32(31))),
            _mm256_set1_epi32(1));
        __m256 vPrime = _mm256_blendv_ps(
            _mm256_set1_ps(epsilon), _mm256_set1_ps(1.0f),
            _mm256_castsi256_ps(_mm256_sub_epi32(_mm256_setzero_si256(), bit)));  // 1 -> all ones

        __m256 base =
            _mm256_mul_ps(_mm256_mul_ps(gatherField(texels, word, 7), gatherField(texels, word, 6)),
                          _mm256_set1_ps(float(M_1_PI)));
        __m256 s = _mm256_mul_ps(_mm256_mul_ps(base, geometry), vPrime);

        // Zero: off the image, no valid texel, |d| = 0, and a weight that is not finite
        // (s - s is 0 exactly for finite s).
        __m256 finite = _mm256_cmp_ps(_mm256_sub_ps(s, s), _mm256_setzero_ps(), _CMP_EQ_OQ);
        __m256 positiveDistance = _mm256_cmp_ps(dist2, _mm256_setzero_ps(), _CMP_GT_OQ);
        __m256 mask =
            _mm256_and_ps(_mm256_and_ps(finite, positiveDistance), _mm256_castsi256_ps(keep));
        return _mm256_and_ps(s, mask);
    }
};

}  // namespace

void ImageGuide::candidates(const OffsetLanes& offsets, int px, int py, const PathVertex& anchor,
                            CandidateWeights& out) const {
    constexpr size_t kLanes = OffsetLanes::kLanes;
    static_assert(kLanes == 8);
    LaneKernel kernel{reinterpret_cast<const float*>(gbuffer_->texels().data()),
                      reinterpret_cast<const int*>(masks_->bits(partition_)),
                      width(),
                      height(),
                      _mm256_set1_ps(anchor.p.x),
                      _mm256_set1_ps(anchor.p.y),
                      _mm256_set1_ps(anchor.p.z),
                      _mm256_set1_ps(anchor.ng.x),
                      _mm256_set1_ps(anchor.ng.y),
                      _mm256_set1_ps(anchor.ng.z),
                      anchor.atInfinity,
                      !isBlack(anchor.ng),
                      masks_->epsilon()};
    out.weights.resize(offsets.count);
    out.sum = 0;
    const __m256i x0 = _mm256_set1_epi32(px), y0 = _mm256_set1_epi32(py);
    alignas(32) float lane[kLanes];
    for (size_t k = 0; k < offsets.count; k += kLanes) {
        __m256i x = _mm256_add_epi32(
            x0, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(&offsets.dx[k])));
        __m256i y = _mm256_add_epi32(
            y0, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(&offsets.dy[k])));
        _mm256_store_ps(lane, kernel(x, y));
        size_t n = std::min(kLanes, offsets.count - k);
        for (size_t j = 0; j < n; ++j) {
            out.weights[k + j] = lane[j];
            out.sum += double(lane[j]);
        }
    }
}

#else  // !__AVX2__

void ImageGuide::candidates(const OffsetLanes& offsets, int px, int py, const PathVertex& anchor,
                            CandidateWeights& out) const {
    gatherCandidates(
        offsets.count,
        [&](size_t k) {
            return PixelOffset{offsets.dx[k], offsets.dy[k]};
        },
        px, py, width(), height(), [&](int x, int y) { return sPrime(x, y, anchor); }, out);
}

#endif

}  // namespace partita
