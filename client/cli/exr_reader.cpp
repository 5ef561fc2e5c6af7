#include "cli/exr_reader.h"

#include <zlib.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "cli/errors.h"
#include "cli/file_util.h"

namespace partita::cli {

namespace {

constexpr int32_t kMagic = 20000630;
enum Compression : uint8_t { kNone = 0, kRle = 1, kZips = 2, kZip = 3 };
const char* const kCompressionNames[] = {"none",  "rle", "zips", "zip",  "piz",
                                         "pxr24", "b44", "b44a", "dwaa", "dwab"};

struct Channel {
    std::string name;
    int32_t type = 0;  // 0 UINT, 1 HALF, 2 FLOAT
    int32_t xSampling = 1, ySampling = 1;
    size_t bytes() const { return type == 1 ? 2 : 4; }
};

class Failure {
  public:
    explicit Failure(std::string file) : file_(std::move(file)) {}
    [[noreturn]] void operator()(const std::string& why) const {
        throw CliError("cannot read EXR '" + file_ + "': " + why);
    }

  private:
    std::string file_;
};

class Cursor {
  public:
    Cursor(const std::string& data, size_t pos, const Failure& fail)
        : data_(data), pos_(pos), fail_(fail) {}
    template <class T>
    T read() {
        need(sizeof(T));
        T v;
        std::memcpy(&v, data_.data() + pos_, sizeof(T));
        pos_ += sizeof(T);
        return v;
    }
    std::string cstring() {
        size_t end = data_.find('\0', pos_);
        if (end == std::string::npos) fail_("truncated header");
        std::string s = data_.substr(pos_, end - pos_);
        pos_ = end + 1;
        return s;
    }
    std::string bytes(size_t n) {
        need(n);
        std::string s = data_.substr(pos_, n);
        pos_ += n;
        return s;
    }
    size_t pos() const { return pos_; }

  private:
    void need(size_t n) const {
        if (pos_ + n > data_.size()) fail_("truncated file");
    }
    const std::string& data_;
    size_t pos_;
    const Failure& fail_;
};

float halfToFloat(uint16_t h) {
    const uint32_t sign = uint32_t(h >> 15) << 31;
    int32_t exponent = (h >> 10) & 0x1f;
    uint32_t mantissa = h & 0x3ff;
    uint32_t bits;
    if (exponent == 0x1f) {
        bits = sign | 0x7f800000u | (mantissa << 13);  // inf / NaN
    } else if (exponent != 0) {
        bits = sign | uint32_t(exponent + 112) << 23 | (mantissa << 13);
    } else if (mantissa == 0) {
        bits = sign;
    } else {  // subnormal half: normalise
        exponent = 113;
        while (!(mantissa & 0x400)) {
            mantissa <<= 1;
            --exponent;
        }
        bits = sign | uint32_t(exponent) << 23 | ((mantissa & 0x3ff) << 13);
    }
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}

/// ZIP and RLE store the bytes delta-coded and split into even/odd halves: undo both.
std::vector<uint8_t> undoPredictorAndInterleave(std::vector<uint8_t> t) {
    for (size_t i = 1; i < t.size(); ++i) t[i] = uint8_t(t[i - 1] + t[i] - 128);
    std::vector<uint8_t> out(t.size());
    const size_t half = (t.size() + 1) / 2;
    for (size_t i = 0; i < half; ++i) out[2 * i] = t[i];
    for (size_t i = half; i < t.size(); ++i) out[2 * (i - half) + 1] = t[i];
    return out;
}

std::vector<uint8_t> rleDecode(const char* data, size_t size, size_t expected,
                               const Failure& fail) {
    std::vector<uint8_t> out;
    out.reserve(expected);
    size_t i = 0;
    while (i < size) {
        const int count = int(static_cast<signed char>(data[i++]));
        if (count < 0) {
            if (i + size_t(-count) > size) fail("corrupt RLE data");
            out.insert(out.end(), data + i, data + i + (-count));
            i += size_t(-count);
        } else {
            if (i >= size) fail("corrupt RLE data");
            out.insert(out.end(), size_t(count) + 1, uint8_t(data[i++]));
        }
        if (out.size() > expected) fail("corrupt RLE data");
    }
    if (out.size() != expected) fail("corrupt RLE data");
    return out;
}

}  // namespace

LayeredImage readExrFile(const std::filesystem::path& path,
                         std::map<std::string, std::string>* attributes) {
    const Failure fail(path.string());
    std::string data;
    try {
        data = readFile(path);
    } catch (const std::exception&) {
        std::error_code ec;
        fail(std::filesystem::exists(path, ec) ? "cannot open it" : "no such file");
    }
    Cursor header(data, 0, fail);
    if (header.read<int32_t>() != kMagic) fail("not an OpenEXR file");
    const int32_t version = header.read<int32_t>();
    if (version & 0x200) fail("tiled EXRs are not supported");
    if (version & 0x800) fail("deep EXRs are not supported");
    if (version & 0x1000) fail("multi-part EXRs are not supported");

    std::vector<Channel> channels;
    int compression = -1;
    std::array<int32_t, 4> window{};
    bool haveWindow = false;
    std::map<std::string, std::string> strings;
    while (true) {
        const std::string name = header.cstring();
        if (name.empty()) break;
        const std::string type = header.cstring();
        const int32_t size = header.read<int32_t>();
        if (size < 0) fail("bad attribute size");
        const std::string value = header.bytes(size_t(size));
        Cursor v(value, 0, fail);
        if (type == "chlist") {
            while (true) {
                Channel c;
                c.name = v.cstring();
                if (c.name.empty()) break;
                c.type = v.read<int32_t>();
                v.read<uint32_t>();  // pLinear + reserved
                c.xSampling = v.read<int32_t>();
                c.ySampling = v.read<int32_t>();
                channels.push_back(c);
            }
        } else if (type == "compression" && name == "compression") {
            compression = uint8_t(value.empty() ? 255 : value[0]);
        } else if (type == "box2i" && name == "dataWindow") {
            for (auto& w : window) w = v.read<int32_t>();
            haveWindow = true;
        } else if (type == "string") {
            strings[name] = value;
        }
    }
    if (channels.empty() || compression < 0 || !haveWindow) fail("incomplete header");
    if (compression > kZip) {
        fail(std::string("compression '") +
             (compression < 10 ? kCompressionNames[compression] : "unknown") +
             "' is not supported (partita writes zip)");
    }
    const int width = window[2] - window[0] + 1, height = window[3] - window[1] + 1;
    if (width <= 0 || height <= 0 || int64_t(width) * height > (int64_t(1) << 31))
        fail("bad data window");
    size_t rowBytes = 0;
    for (const auto& c : channels) {
        if (c.type < 0 || c.type > 2) fail("channel '" + c.name + "' has an unknown pixel type");
        if (c.xSampling != 1 || c.ySampling != 1)
            fail("channel '" + c.name + "' is subsampled, which is not supported");
        rowBytes += c.bytes() * size_t(width);
    }

    const int linesPerBlock = compression == kZip ? 16 : 1;
    const int blocks = (height + linesPerBlock - 1) / linesPerBlock;
    std::vector<uint64_t> offsets(static_cast<size_t>(blocks));
    for (auto& o : offsets) o = header.read<uint64_t>();

    std::vector<std::vector<float>> planes(channels.size(),
                                           std::vector<float>(size_t(width) * height));
    for (uint64_t offset : offsets) {
        if (offset > data.size()) fail("bad offset table");
        Cursor block(data, size_t(offset), fail);
        const int32_t y = block.read<int32_t>() - window[1];
        const int32_t size = block.read<int32_t>();
        if (y < 0 || y >= height || size < 0 || block.pos() + size_t(size) > data.size())
            fail("bad block");
        const int lines = std::min(linesPerBlock, height - y);
        const size_t expected = rowBytes * size_t(lines);
        const char* payload = data.data() + block.pos();
        std::vector<uint8_t> raw;
        if (size_t(size) == expected || compression == kNone) {
            raw.assign(payload, payload + size);
        } else if (compression == kRle) {
            raw = undoPredictorAndInterleave(rleDecode(payload, size_t(size), expected, fail));
        } else {
            std::vector<uint8_t> unpacked(expected);
            uLongf length = uLongf(expected);
            if (uncompress(unpacked.data(), &length, reinterpret_cast<const Bytef*>(payload),
                           uLong(size)) != Z_OK ||
                length != expected)
                fail("corrupt ZIP block");
            raw = undoPredictorAndInterleave(std::move(unpacked));
        }
        if (raw.size() != expected) fail("block has the wrong size");
        size_t pos = 0;
        for (int line = 0; line < lines; ++line)
            for (size_t c = 0; c < channels.size(); ++c) {
                float* dst = &planes[c][size_t(y + line) * width];
                for (int x = 0; x < width; ++x) {
                    const uint8_t* p = raw.data() + pos;
                    if (channels[c].type == 2) {
                        std::memcpy(&dst[x], p, 4);
                    } else if (channels[c].type == 1) {
                        uint16_t h;
                        std::memcpy(&h, p, 2);
                        dst[x] = halfToFloat(h);
                    } else {
                        uint32_t u;
                        std::memcpy(&u, p, 4);
                        dst[x] = float(u);
                    }
                    pos += channels[c].bytes();
                }
            }
    }

    auto index = [&](const std::string& name) -> int {
        for (size_t c = 0; c < channels.size(); ++c)
            if (channels[c].name == name) return int(c);
        return -1;
    };
    auto extract = [&](int r, int g, int b) {
        Image img(width, height);
        const size_t n = size_t(width) * height;
        for (size_t p = 0; p < n; ++p) {
            img.rgb[p * 3 + 0] = planes[size_t(r)][p];
            img.rgb[p * 3 + 1] = planes[size_t(g)][p];
            img.rgb[p * 3 + 2] = planes[size_t(b)][p];
        }
        return img;
    };

    LayeredImage image;
    if (index("R") >= 0 && index("G") >= 0 && index("B") >= 0)
        image.combined = extract(index("R"), index("G"), index("B"));
    else if (channels.size() >= 3)
        image.combined = extract(0, 1, 2);
    else
        image.combined = extract(0, 0, 0);

    std::vector<std::string> names;
    if (auto it = strings.find("partita:layers"); it != strings.end()) {
        size_t start = 0;
        while (start <= it->second.size()) {
            size_t comma = it->second.find(',', start);
            if (comma == std::string::npos) comma = it->second.size();
            if (comma > start) names.push_back(it->second.substr(start, comma - start));
            start = comma + 1;
        }
    }
    for (const auto& c : channels) {
        const size_t dot = c.name.rfind('.');
        if (dot == std::string::npos || dot == 0) continue;
        const std::string base = c.name.substr(0, dot);
        bool seen = false;
        for (const auto& n : names) seen = seen || n == base;
        if (!seen) names.push_back(base);
    }
    for (const auto& n : names) {
        const int r = index(n + ".R"), g = index(n + ".G"), b = index(n + ".B");
        if (r >= 0 && g >= 0 && b >= 0) image.layers.push_back({n, extract(r, g, b)});
    }
    if (attributes) {
        strings.erase("partita:layers");
        *attributes = std::move(strings);
    }
    return image;
}

}  // namespace partita::cli
