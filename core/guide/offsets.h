// The offset set Delta of the guided image perturbation (paper Eq. 18, Sec. 5.1.2): the pixel
// shifts that, added to the current path's pixel p, give the candidate pixels Y'(p).
//
// Reversibility needs q in Y'(p) exactly when p in Y'(q), with the same multiplicity: Delta is
// symmetric under negation. Its first half comes from a low-discrepancy sequence (Halton, bases
// 2 and 3) mapped to the disk of radius R by (r, theta) = (R zeta_x^2, 2 pi zeta_y), which
// concentrates candidates near the current pixel (the paper finds that advantageous), rounded
// to whole pixels; then the centre (0, 0); then the negations of the first half.
//
// |Y'| odd: (|Y'| - 1) / 2 offsets, the centre, their negations. |Y'| even (the paper's 128):
// the same with (|Y'| - 2) / 2 offsets and the centre twice, so that |Delta| = |Y'| and Delta
// stays symmetric. Rounding makes some offsets collide (several near the centre round to
// (0, 0)): a collision is a multiplicity, which the proposal's T counts (guided_choice.h).
#pragma once

#include <cstddef>
#include <vector>

namespace partita {

struct PixelOffset {
    int dx = 0, dy = 0;
    bool operator==(const PixelOffset&) const = default;
};

/// Delta for |Y'| = `count` (>= 1) candidates in a disk of `radius` pixels (>= 0). paper Eq. 18
std::vector<PixelOffset> guideOffsets(int count, float radius);

/// Delta laid out for the candidate sums' vector loop (image_guide.h ImageGuide::candidates):
/// the shifts' dx and dy apart, padded to a whole number of lanes with a shift that leaves any
/// image (its weight is 0, and it is never returned).
struct OffsetLanes {
    static constexpr size_t kLanes = 8;  // floats in an AVX2 register
    explicit OffsetLanes(const std::vector<PixelOffset>& delta);
    size_t count = 0;         // |Delta|
    std::vector<int> dx, dy;  // count rounded up to kLanes
};

/// For each k, an index j with delta_j = -delta_k (the move back from p + delta_k to p).
/// Throws std::invalid_argument when `delta` is not symmetric: a shift not exactly as often in
/// it as its negation (the guided move's ratio needs that, guided_choice.h).
std::vector<int> oppositeOffsets(const std::vector<PixelOffset>& delta);

}  // namespace partita
