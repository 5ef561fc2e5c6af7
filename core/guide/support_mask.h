// The thresholded denoised pre-pass images, stored compactly: Eq. 17 reads D_i only through
// D_i(q) > epsilon, so one bit a pixel and partition is all the guided proposal keeps of D_i
// (11 partitions at 1280x720: 1.3 MB, against 40.6 MB as floats), next to the G-buffer (40 B a
// pixel: 36.9 MB). The V' of Eq. 17 itself belongs to guide/image_guide.h.
//
// And how good a thresholded D_i is: against a reference image of the partition (a long render's
// layers of its types), the fraction of the pixels where the reference is non-zero that D_i
// keeps above epsilon (V' = 1 there: the proposal can reach them at full weight), and of the
// pixels where it is zero that D_i puts at or below epsilon (V' = epsilon: the proposal avoids
// them).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace partita {

class SupportMasks {
  public:
    SupportMasks() = default;
    /// Bit (i, pixel) = denoised[i][pixel] > epsilon, for images of width * height each.
    /// std::invalid_argument when an image has another size.
    SupportMasks(const std::vector<std::vector<float>>& denoised, int width, int height,
                 float epsilon);

    int width() const { return width_; }
    int height() const { return height_; }
    size_t partitions() const { return masks_.size(); }
    float epsilon() const { return epsilon_; }
    /// Whether D_i > epsilon at pixel (x, y), x in [0, width), y in [0, height).
    bool above(size_t partition, int x, int y) const {
        size_t p = size_t(y) * size_t(width_) + size_t(x);
        return (masks_[partition][p >> 6] >> (p & 63)) & 1u;
    }
    /// Partition i's bits, bit (y * width + x) of the little-endian words.
    const uint64_t* bits(size_t partition) const { return masks_[partition].data(); }
    /// Memory held by the bits.
    size_t bytes() const;

    /// A binary form (for a shard plan); deserialize throws std::invalid_argument on anything
    /// else.
    std::vector<uint8_t> serialize() const;
    static SupportMasks deserialize(std::span<const uint8_t> bytes);

  private:
    int width_ = 0, height_ = 0;
    float epsilon_ = 0;
    std::vector<std::vector<uint64_t>> masks_;
};

struct SupportAgreement {
    size_t referenceNonzero = 0, referenceZero = 0;  // pixels of each kind in the reference
    double nonzeroAbove = 0;  // fraction of reference-non-zero pixels with D > epsilon (V' = 1)
    double zeroBelow = 0;     // fraction of reference-zero pixels with D <= epsilon (V' = eps)
};

/// How the threshold of `denoised` at epsilon agrees with the support of `reference` (pixels
/// with reference > referenceFloor count as non-zero), both width * height luminance images of
/// one partition. A fraction over no pixel is 1. std::invalid_argument for different sizes.
SupportAgreement supportAgreement(const std::vector<float>& denoised,
                                  const std::vector<float>& reference, float epsilon,
                                  float referenceFloor = 0);

}  // namespace partita
