#include "preview_png.h"

#include <zlib.h>

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "image_io.h"

namespace partita::server {

namespace {

void putU32(std::string& out, uint32_t v) {
    out.push_back(char(v >> 24));
    out.push_back(char(v >> 16));
    out.push_back(char(v >> 8));
    out.push_back(char(v));
}

/// Length, type, data, CRC of type + data (PNG specification, section 5.3).
void putChunk(std::string& out, const char type[4], const std::string& data) {
    putU32(out, uint32_t(data.size()));
    size_t start = out.size();
    out.append(type, 4);
    out += data;
    uLong crc =
        crc32(0L, reinterpret_cast<const Bytef*>(out.data() + start), uInt(out.size() - start));
    putU32(out, uint32_t(crc));
}

/// encodeSrgb8 through a table: the positive floats below 1 in buckets of their top bits (8
/// exponent bits, 10 mantissa bits). encodeSrgb8 is monotone, so a bucket whose two ends give the
/// same code gives it for every value inside; the few buckets that straddle a code boundary ask
/// encodeSrgb8 itself. Same result as encodeSrgb8 for every float, ~10x faster.
class SrgbTable {
  public:
    SrgbTable() : codes_(kBuckets) {
        for (uint32_t k = 0; k < kBuckets; ++k) {
            uint8_t lo = encodeSrgb8(fromBits(k << kShift)),
                    hi = encodeSrgb8(fromBits(((k + 1) << kShift) - 1));
            codes_[k] = lo == hi ? lo : kAmbiguous;
        }
    }
    uint8_t operator()(float v) const {
        if (!(v > 0.0f)) return 0;
        if (v >= 1.0f) return 255;
        uint32_t bits;
        std::memcpy(&bits, &v, 4);
        uint16_t code = codes_[bits >> kShift];
        return code == kAmbiguous ? encodeSrgb8(v) : uint8_t(code);
    }

  private:
    static float fromBits(uint32_t bits) {
        float f;
        std::memcpy(&f, &bits, 4);
        return f;
    }
    static constexpr uint32_t kShift = 13;
    static constexpr uint32_t kBuckets = 0x3F800000u >> kShift;  // every bucket below 1.0f
    static constexpr uint16_t kAmbiguous = 0xffff;
    std::vector<uint16_t> codes_;
};

}  // namespace

std::string encodePreviewPng(const Image& image, float exposureStops) {
    const int w = image.width, h = image.height;
    if (w <= 0 || h <= 0 || image.rgb.size() != size_t(w) * size_t(h) * 3)
        throw std::runtime_error("cannot encode PNG: the image is empty or malformed");
    const float scale = std::exp2(exposureStops);
    static const SrgbTable srgb;

    // Filtered scanlines: a filter-type byte (1 = Sub) then each byte minus the one 3 to its left.
    const size_t rowBytes = size_t(w) * 3;
    std::vector<uint8_t> raw((rowBytes + 1) * size_t(h));
    std::vector<uint8_t> row(rowBytes);
    for (int y = 0; y < h; ++y) {
        const float* src = image.rgb.data() + size_t(y) * rowBytes;
        for (size_t i = 0; i < rowBytes; ++i) row[i] = srgb(src[i] * scale);
        uint8_t* dst = raw.data() + size_t(y) * (rowBytes + 1);
        dst[0] = 1;
        for (size_t i = 0; i < rowBytes; ++i)
            dst[i + 1] = uint8_t(row[i] - (i >= 3 ? row[i - 3] : 0));
    }

    uLongf compressedSize = compressBound(uLong(raw.size()));
    std::string idat(compressedSize, '\0');
    if (compress2(reinterpret_cast<Bytef*>(idat.data()), &compressedSize, raw.data(),
                  uLong(raw.size()), 1) != Z_OK)
        throw std::runtime_error("cannot encode PNG: zlib failed");
    idat.resize(compressedSize);

    std::string png("\x89PNG\r\n\x1a\n", 8);
    std::string ihdr;
    putU32(ihdr, uint32_t(w));
    putU32(ihdr, uint32_t(h));
    ihdr += std::string("\x08\x02\x00\x00\x00",
                        5);  // 8 bits, RGB, deflate, no filter set, no interlace
    putChunk(png, "IHDR", ihdr);
    putChunk(png, "sRGB", std::string(1, '\0'));  // perceptual rendering intent
    putChunk(png, "IDAT", idat);
    putChunk(png, "IEND", "");
    return png;
}

}  // namespace partita::server
