#include "guide/support_mask.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "byte_stream.h"

namespace partita {

SupportMasks::SupportMasks(const std::vector<std::vector<float>>& denoised, int width, int height,
                           float epsilon)
    : width_(std::max(0, width)), height_(std::max(0, height)), epsilon_(epsilon) {
    size_t pixels = size_t(width_) * size_t(height_);
    for (const std::vector<float>& d : denoised) {
        if (d.size() != pixels)
            throw std::invalid_argument("SupportMasks: an image's size is not width * height");
        std::vector<uint64_t> bits((pixels + 63) / 64, 0);
        for (size_t p = 0; p < pixels; ++p)
            if (d[p] > epsilon) bits[p >> 6] |= uint64_t(1) << (p & 63);
        masks_.push_back(std::move(bits));
    }
}

size_t SupportMasks::bytes() const {
    size_t b = 0;
    for (const std::vector<uint64_t>& m : masks_) b += m.size() * sizeof(uint64_t);
    return b;
}

std::vector<uint8_t> SupportMasks::serialize() const {
    ByteWriter w;
    w.put(int32_t(width_));
    w.put(int32_t(height_));
    w.put(epsilon_);
    w.put(uint64_t(masks_.size()));
    for (const std::vector<uint64_t>& m : masks_) w.putRaw(m.data(), m.size() * sizeof(uint64_t));
    return std::move(w.bytes);
}

SupportMasks SupportMasks::deserialize(std::span<const uint8_t> bytes) {
    ByteReader r(bytes, "support masks");
    SupportMasks s;
    s.width_ = r.get<int32_t>();
    s.height_ = r.get<int32_t>();
    s.epsilon_ = r.get<float>();
    if (s.width_ < 0 || s.height_ < 0 || int64_t(s.width_) * s.height_ > (int64_t(1) << 28))
        r.fail("bad size");
    const uint64_t partitions = r.get<uint64_t>();
    const size_t words = (size_t(s.width_) * size_t(s.height_) + 63) / 64;
    for (uint64_t i = 0; i < partitions; ++i) {
        std::span<const uint8_t> raw = r.getRaw(words * sizeof(uint64_t));
        std::vector<uint64_t> bits(words);
        std::memcpy(bits.data(), raw.data(), raw.size());
        s.masks_.push_back(std::move(bits));
    }
    if (!r.atEnd()) r.fail("trailing bytes");
    return s;
}

SupportAgreement supportAgreement(const std::vector<float>& denoised,
                                  const std::vector<float>& reference, float epsilon,
                                  float referenceFloor) {
    if (denoised.size() != reference.size())
        throw std::invalid_argument("supportAgreement: the images differ in size");
    SupportAgreement a;
    size_t above = 0, below = 0;
    for (size_t p = 0; p < reference.size(); ++p) {
        bool kept = denoised[p] > epsilon;
        if (reference[p] > referenceFloor) {
            ++a.referenceNonzero;
            above += kept;
        } else {
            ++a.referenceZero;
            below += !kept;
        }
    }
    a.nonzeroAbove = a.referenceNonzero ? double(above) / double(a.referenceNonzero) : 1.0;
    a.zeroBelow = a.referenceZero ? double(below) / double(a.referenceZero) : 1.0;
    return a;
}

}  // namespace partita
