// The discrete part of the guided image perturbation (paper Sec. 5.1, Eq. 16): from the pixel p
// of the current path, the candidates Y'(p) = {p + delta : delta in Delta} (offsets.h) with
// weights S'(q) (image_guide.h, Eq. 15; 0 off the image), one chosen in proportion to its
// weight. A pixel q reached by several offsets (rounding collisions) is proposed with the sum
// of their weights: its multiplicity. The move's density on the image plane is that
// probability over the pixel's area (a uniform jitter inside q), so the ratio of Eq. 16's
// proposal densities is
//   T(x' -> x) / T(x -> x') = P(p | Y'(q)) / P(q | Y'(p))
//                           = [m S'(p) / sum_{Y'(q)} S'] / [m S'(q) / sum_{Y'(p)} S'],
// m the multiplicity (the same both ways: Delta is symmetric). Pure functions of the weights,
// shared by the real mutation (guided_perturbation.h) and the exact transition-matrix test.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "guide/offsets.h"

namespace partita {

struct CandidateWeights {
    std::vector<float> weights;  // S'(p + delta_k) for each k of Delta
    double sum = 0;
};

/// Fills `out` with S'(p + delta_k) for k < count, delta_k = offsetAt(k) (a PixelOffset):
/// sPrime(x, y) for pixels on the width x height image, 0 off it. The plain form, for any weight
/// function and offset storage (the exact transition-matrix test's grids, the portable build);
/// with AVX2 the guided move uses ImageGuide::candidates, the same for the G-buffer's S'.
template <typename OffsetAt, typename SPrime>
void gatherCandidates(size_t count, OffsetAt&& offsetAt, int px, int py, int width, int height,
                      SPrime&& sPrime, CandidateWeights& out) {
    out.weights.resize(count);
    out.sum = 0;
    for (size_t k = 0; k < count; ++k) {
        const PixelOffset delta = offsetAt(k);
        int x = px + delta.dx, y = py + delta.dy;
        bool onImage = x >= 0 && y >= 0 && x < width && y < height;
        float w = onImage ? float(sPrime(x, y)) : 0.0f;
        out.weights[k] = w;
        out.sum += double(w);
    }
}

/// gatherCandidates over the offsets of Delta.
template <typename SPrime>
void gatherCandidates(const std::vector<PixelOffset>& delta, int px, int py, int width, int height,
                      SPrime&& sPrime, CandidateWeights& out) {
    gatherCandidates(
        delta.size(), [&](size_t k) { return delta[k]; }, px, py, width, height,
        std::forward<SPrime>(sPrime), out);
}

/// The index k chosen with probability w_k / sum, from u in [0, 1); -1 when the sum is 0.
int chooseCandidate(const CandidateWeights& candidates, double u);

/// T(x' -> x) / T(x -> x') of a move from pixel p to q = p + delta_k, in image-plane measure
/// (the pixel areas cancel). `atP` and `atQ` are the candidates around p and q, `back` an index
/// with delta_back = -delta_k (offsets.h oppositeOffsets). Every offset that reaches q from p
/// carries the weight S'(q), and as many reach p from q, so the multiplicity m cancels:
///   [m S'(p) / sum_{Y'(q)} S'] / [m S'(q) / sum_{Y'(p)} S'],
/// S'(q) = atP.weights[k] and S'(p) = atQ.weights[back]. 0 when the reverse move is impossible
/// (S'(p) = 0 seen from q); the forward move must have been possible (atP.weights[k] > 0).
/// paper Eq. 16
double guidedProposalRatio(const CandidateWeights& atP, const CandidateWeights& atQ, int k,
                           int back);

}  // namespace partita
