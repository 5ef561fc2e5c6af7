#include "image_io.h"

#include <fcntl.h>
#include <unistd.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <stdexcept>
#include <system_error>

#include "exr_header.h"

namespace partita {

namespace fs = std::filesystem;

namespace {

constexpr const char* kLayerOrderAttribute = "partita:layers";

std::string quoted(const fs::path& p) {
    std::string s(1, '\'');
    s += p.string();
    s += '\'';
    return s;
}

/// fsync a file or directory; best effort (a failure here does not lose the data written).
void syncPath(const fs::path& p, bool directory) {
    int fd = ::open(p.c_str(), O_RDONLY | (directory ? O_DIRECTORY : 0));
    if (fd < 0) return;
    ::fsync(fd);
    ::close(fd);
}

/// Write a file atomically: `writeTmp` writes the content to the temporary path it is given and
/// returns an error message ("" on success); the file is then flushed and renamed over `path`.
void writeAtomically(const fs::path& path, const char* what,
                     const std::function<std::string(const fs::path&)>& writeTmp) {
    const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        throw std::runtime_error(std::string("cannot write ") + what + " " + quoted(path) +
                                 ": directory " + quoted(dir) + " does not exist");
    if (fs::is_directory(path, ec))
        throw std::runtime_error(std::string("cannot write ") + what + " " + quoted(path) +
                                 ": it is a directory");

    // pid for processes sharing a folder, a counter for threads of this process.
    static std::atomic<unsigned> counter{0};
    fs::path tmp = path;
    tmp += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));

    std::string error = writeTmp(tmp);
    if (error.empty()) {
        syncPath(tmp, false);
        fs::rename(tmp, path, ec);
        if (ec) error = "rename from " + quoted(tmp) + " failed: " + ec.message();
    }
    if (!error.empty()) {
        fs::remove(tmp, ec);
        throw std::runtime_error(std::string("cannot write ") + what + " " + quoted(path) + ": " +
                                 error);
    }
    syncPath(dir, true);
}

std::string oiioError(const OIIO::ImageOutput* out) {
    std::string e = out ? out->geterror() : std::string();
    if (e.empty()) e = OIIO::geterror();
    return e.empty() ? "unknown OpenImageIO error" : e;
}

std::string oiioError(const OIIO::ImageInput* in) {
    std::string e = in ? in->geterror() : std::string();
    if (e.empty()) e = OIIO::geterror();
    return e.empty() ? "unknown OpenImageIO error" : e;
}

std::vector<std::string> splitLayerOrder(const std::string& s) {
    std::vector<std::string> out;
    size_t start = 0;
    while (start <= s.size()) {
        size_t end = s.find(',', start);
        if (end == std::string::npos) end = s.size();
        if (end > start) out.push_back(s.substr(start, end - start));
        start = end + 1;
    }
    return out;
}

/// Linear values at which the 8-bit code steps from b-1 to b (b = 1..255): the inverse sRGB
/// curve at (b - 0.5) / 255. Counting the thresholds <= v is rounding the exact curve to the
/// nearest code (halves up) without a pow per value.
const std::array<double, 255>& srgbThresholds() {
    static const std::array<double, 255> table = [] {
        std::array<double, 255> t{};
        for (int b = 1; b <= 255; ++b) {
            const double e = (b - 0.5) / 255.0;
            t[b - 1] = e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
        }
        return t;
    }();
    return table;
}

/// encodeSrgb8 by a binary search of the thresholds: the exact definition.
uint8_t encodeSrgb8Exact(float linear) {
    if (!(linear > 0.0f)) return 0;  // negative, zero and NaN
    if (linear >= 1.0f) return 255;
    const auto& t = srgbThresholds();
    return uint8_t(std::upper_bound(t.begin(), t.end(), double(linear)) - t.begin());
}

/// encodeSrgb8Exact through a small table and one compare. The floats in [2^-13, 1) fall in
/// buckets of their top bits (exponent and 10 mantissa bits); a bucket is narrower than the gap
/// between two code boundaries (checked when the table is built), so a value's code is its
/// bucket's first code, plus one if the value reaches the next boundary. Boundaries are kept as
/// the smallest float at or above the double threshold, so the float compare decides as the
/// exact search would. Everything below 2^-13 is below the first boundary (code 0). The same
/// result for every float as encodeSrgb8Exact, and the table (13 KiB) stays in cache: the
/// conversion dominated encoding a PNG with fast compression.
class SrgbTable {
  public:
    SrgbTable() : codes_(kBuckets) {
        const auto& t = srgbThresholds();
        for (size_t b = 0; b < t.size(); ++b) {
            float f = float(t[b]);
            if (double(f) < t[b]) f = std::nextafter(f, 2.0f);
            boundary_[b] = f;
        }
        boundary_[255] = std::numeric_limits<float>::infinity();
        if (!(fromBits(kLowBits) < boundary_[0]))
            throw std::logic_error("sRGB table: the first bucket starts above the first boundary");
        for (uint32_t k = 0; k < kBuckets; ++k) {
            const uint8_t lo = encodeSrgb8Exact(fromBits(kLowBits + (k << kShift))),
                          hi = encodeSrgb8Exact(fromBits(kLowBits + ((k + 1) << kShift) - 1));
            if (hi > lo + 1) throw std::logic_error("sRGB table: a bucket spans two boundaries");
            codes_[k] = lo;
        }
    }
    uint8_t operator()(float v) const {
        // Without branches (noisy pixels would mispredict them): the bits clamped into the
        // table's range, then the values outside it overridden.
        uint32_t bits;
        std::memcpy(&bits, &v, 4);
        const uint32_t c = std::min(std::max(bits, kLowBits), kOneBits - 1);
        const uint32_t lo = codes_[(c - kLowBits) >> kShift];
        // Below 2^-13, v is below boundary_[0] and lo is 0.
        uint32_t code = lo + (v >= boundary_[lo] ? 1u : 0u);
        code = bits >= kOneBits ? 255u : code;  // 1 and above, +infinity
        code = bits > kInfBits ? 0u : code;     // negative (-0 too) and NaN
        return uint8_t(code);
    }

  private:
    static float fromBits(uint32_t bits) {
        float f;
        std::memcpy(&f, &bits, 4);
        return f;
    }
    static constexpr uint32_t kShift = 13;             // 10 mantissa bits kept
    static constexpr uint32_t kLowBits = 0x39000000u;  // 2^-13
    static constexpr uint32_t kOneBits = 0x3F800000u;  // 1.0f
    static constexpr uint32_t kInfBits = 0x7F800000u;  // +infinity
    static constexpr uint32_t kBuckets = (kOneBits - kLowBits) >> kShift;
    std::vector<uint8_t> codes_;
    std::array<float, 256> boundary_{};  // code b steps to b + 1 at boundary_[b]
};

const SrgbTable& srgbTable() {
    static const SrgbTable table;
    return table;
}

/// Rows an EXR is written in at a time (a multiple of the 16 rows of a zip block).
constexpr int kExrStripRows = 64;

/// Rows [y0, y1) of the combined image and the layers, pixel by pixel with all nch channels.
void interleaveRows(const LayeredImage& image, int y0, int y1, size_t nch, float* out) {
    const size_t w = size_t(image.combined.width);
    for (size_t p = size_t(y0) * w; p < size_t(y1) * w; ++p) {
        float* dst = out + (p - size_t(y0) * w) * nch;
        for (int k = 0; k < 3; ++k) dst[k] = image.combined.rgb[p * 3 + size_t(k)];
        for (size_t l = 0; l < image.layers.size(); ++l)
            for (int k = 0; k < 3; ++k)
                dst[3 + l * 3 + size_t(k)] = image.layers[l].image.rgb[p * 3 + size_t(k)];
    }
}

}  // namespace

void writeExr(const fs::path& path, const LayeredImage& image,
              const std::map<std::string, std::string>& metadata) {
    const int w = image.combined.width, h = image.combined.height;
    auto fail = [&](const std::string& why) {
        throw std::runtime_error("cannot write EXR " + quoted(path) + ": " + why);
    };
    if (w <= 0 || h <= 0) fail("the image is empty");
    if (image.combined.rgb.size() != size_t(w) * h * 3)
        fail("combined image has a wrong buffer size");

    std::vector<std::string> channels = {"R", "G", "B"};
    std::string order;
    for (const auto& layer : image.layers) {
        if (layer.image.width != w || layer.image.height != h ||
            layer.image.rgb.size() != size_t(w) * h * 3)
            fail("layer '" + layer.name + "' is not the size of the combined image");
        if (layer.name.empty() || layer.name.find_first_of(",\n") != std::string::npos)
            fail("invalid layer name '" + layer.name + "'");
        for (const auto& other : image.layers)
            if (&other != &layer && other.name == layer.name)
                fail("duplicate layer name '" + layer.name + "'");
        for (const char* c : {".R", ".G", ".B"}) channels.push_back(layer.name + c);
        order += (order.empty() ? "" : ",") + layer.name;
    }

    OIIO::ImageSpec spec(w, h, int(channels.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames = channels;
    spec.attribute("compression", "zip");
    for (const auto& [key, value] : metadata) spec.attribute(key, value);
    if (!image.layers.empty()) spec.attribute(kLayerOrderAttribute, order);

    writeAtomically(path, "EXR", [&](const fs::path& tmp) -> std::string {
        // By format name: the temporary file's extension does not say "exr".
        auto out = OIIO::ImageOutput::create("exr");
        if (!out) return "no EXR writer: " + oiioError(out.get());
        if (!out->open(tmp.string(), spec)) return oiioError(out.get());
        // A strip of rows at a time, every channel of a pixel interleaved as OIIO expects: a
        // copy of the whole image would double the memory of a many-layer render at its end.
        const size_t nch = channels.size();
        std::vector<float> strip;
        for (int y0 = 0; y0 < h; y0 += kExrStripRows) {
            const int y1 = std::min(h, y0 + kExrStripRows);
            strip.resize(size_t(y1 - y0) * size_t(w) * nch);
            interleaveRows(image, y0, y1, nch, strip.data());
            if (!out->write_scanlines(y0, y1, 0, OIIO::TypeDesc::FLOAT, strip.data())) {
                std::string e = oiioError(out.get());
                out->close();
                return e;
            }
        }
        if (!out->close()) return oiioError(out.get());
        return {};
    });
}

namespace {

/// By default OpenImageIO hands a file that the reader its extension names cannot open to every
/// other format reader in turn. Images here are untrusted (an uploaded environment map) and
/// only EXR and HDR are meant: only the extension's reader may parse them. (It also makes a
/// refusal much cheaper: tests/fuzz/README.md.)
void onlyTheReaderOfTheExtension() {
    static const bool set = OIIO::attribute("try_all_readers", 0);
    (void)set;
}

}  // namespace

ImageHeader readImageHeader(std::span<const uint8_t> bytes, const std::string& name) {
    onlyTheReaderOfTheExtension();
    if (std::string why = exrHeaderProblem(bytes); !why.empty())
        throw std::runtime_error("cannot read image '" + fs::path(name).filename().string() +
                                 "': " + why);
    OIIO::Filesystem::IOMemReader proxy(const_cast<uint8_t*>(bytes.data()), bytes.size());
    auto in = OIIO::ImageInput::open(fs::path(name).filename().string(), nullptr, &proxy);
    if (!in)
        throw std::runtime_error("cannot read image '" + fs::path(name).filename().string() +
                                 "': " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    ImageHeader h{spec.width, spec.height, spec.nchannels};
    in->close();
    return h;
}

LayeredImage readExr(const fs::path& path, std::map<std::string, std::string>* metadata,
                     size_t maxPixels) {
    auto fail = [&](const std::string& why) {
        throw std::runtime_error("cannot read image " + quoted(path) + ": " + why);
    };
    std::error_code ec;
    if (!fs::exists(path, ec)) fail("no such file");
    if (std::string why = exrHeaderProblem(path); !why.empty()) fail(why);
    onlyTheReaderOfTheExtension();
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) fail(oiioError(in.get()));
    const OIIO::ImageSpec spec = in->spec();
    const int w = spec.width, h = spec.height, nch = spec.nchannels;
    if (w <= 0 || h <= 0 || nch <= 0) fail("empty image");
    if (spec.depth > 1) fail("volume images are not supported");
    if (maxPixels > 0 && size_t(w) * size_t(h) > maxPixels)
        fail(std::to_string(w) + " x " + std::to_string(h) + " pixels are more than the " +
             std::to_string(maxPixels) + " allowed");
    const size_t npix = size_t(w) * h;
    std::vector<float> data(npix * nch);
    // Scanline files a line at a time: OpenImageIO 2.4's read_image converts through a buffer of
    // ~64 MiB whatever the image's size (a 3 x 1 HDR allocated 64 MiB; found by
    // fuzz_environment_image), while read_scanline needs one line. Tiled files as a whole.
    const size_t rowFloats = size_t(w) * size_t(nch);
    if (spec.tile_width > 0) {
        if (!in->read_image(0, 0, 0, nch, OIIO::TypeDesc::FLOAT, data.data()))
            fail(oiioError(in.get()));
    } else {
        for (int y = 0; y < h; ++y)
            if (!in->read_scanline(spec.y + y, spec.z, OIIO::TypeDesc::FLOAT,
                                   data.data() + size_t(y) * rowFloats))
                fail(oiioError(in.get()));
    }
    in->close();

    auto channelIndex = [&](const std::string& name) {
        for (int c = 0; c < nch; ++c)
            if (spec.channel_name(c) == name) return c;
        return -1;
    };
    auto extract = [&](const std::array<int, 3>& idx) {
        Image img(w, h);
        for (size_t p = 0; p < npix; ++p)
            for (int k = 0; k < 3; ++k) img.rgb[p * 3 + k] = data[p * nch + idx[k]];
        return img;
    };

    // Layers: complete "<name>.R/.G/.B" triples, by first appearance.
    std::vector<std::pair<std::string, std::array<int, 3>>> found;
    for (int c = 0; c < nch; ++c) {
        const std::string name = spec.channel_name(c);
        const size_t dot = name.rfind('.');
        if (dot == std::string::npos || dot == 0 || dot + 2 != name.size()) continue;
        const int k = name.back() == 'R' ? 0 : name.back() == 'G' ? 1 : name.back() == 'B' ? 2 : -1;
        if (k < 0) continue;
        const std::string layer = name.substr(0, dot);
        auto it = std::find_if(found.begin(), found.end(),
                               [&](const auto& f) { return f.first == layer; });
        if (it == found.end()) it = found.insert(found.end(), {layer, {-1, -1, -1}});
        it->second[k] = c;
    }
    std::erase_if(
        found, [](const auto& f) { return f.second[0] < 0 || f.second[1] < 0 || f.second[2] < 0; });

    // Reorder as writeExr was given them; unknown names keep their place after those.
    const std::vector<std::string> order =
        splitLayerOrder(std::string(spec.get_string_attribute(kLayerOrderAttribute)));
    auto rank = [&](const std::string& name) {
        return size_t(std::find(order.begin(), order.end(), name) - order.begin());
    };
    std::stable_sort(found.begin(), found.end(),
                     [&](const auto& a, const auto& b) { return rank(a.first) < rank(b.first); });

    LayeredImage out;
    const std::array<int, 3> rgb = {channelIndex("R"), channelIndex("G"), channelIndex("B")};
    if (rgb[0] >= 0 && rgb[1] >= 0 && rgb[2] >= 0)
        out.combined = extract(rgb);
    else if (!found.empty())
        out.combined = Image(w, h);  // layers without a combined image
    else if (nch >= 3)
        out.combined = extract({0, 1, 2});
    else
        out.combined = extract({0, 0, 0});
    for (const auto& [name, idx] : found) out.layers.push_back({name, extract(idx)});

    if (metadata) {
        metadata->clear();
        for (const auto& p : spec.extra_attribs) {
            if (p.type() != OIIO::TypeDesc::STRING || p.nvalues() != 1) continue;
            std::string key(p.name());
            if (key == kLayerOrderAttribute) continue;
            (*metadata)[key] = p.get_ustring().string();
        }
    }
    return out;
}

uint8_t encodeSrgb8(float linear) { return srgbTable()(linear); }

std::vector<uint8_t> encodePng(const Image& image, float exposureStops, const PngOptions& options) {
    const int w = image.width, h = image.height;
    if (w <= 0 || h <= 0 || image.rgb.size() != size_t(w) * h * 3)
        throw std::runtime_error("cannot encode PNG: the image is empty or malformed");
    const float scale = std::exp2(exposureStops);
    const SrgbTable& srgb = srgbTable();
    std::vector<uint8_t> pixels(image.rgb.size());
    for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = srgb(image.rgb[i] * scale);

    std::vector<unsigned char> bytes;  // OIIO writes straight into the vector returned
    bytes.reserve(pixels.size() / 2);
    OIIO::Filesystem::IOVecOutput proxy(bytes);
    auto out = OIIO::ImageOutput::create("png");
    if (!out) throw std::runtime_error("cannot encode PNG: no PNG writer: " + oiioError(out.get()));
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB");
    if (options.fast) {
        // Unfiltered rows with zlib's run-length strategy take a fraction of the time of
        // libpng's defaults (level 6, an adaptive choice among all five filters per row), for
        // files ~15% larger. Render previews are noisy, so zlib level 1 with the "Sub" filter,
        // which searched for matches, was both slower and larger than run lengths of raw rows;
        // and the mostly black type layers are long runs of zeros.
        constexpr int kPngFilterNone = 0x08;  // PNG_FILTER_NONE of png.h
        spec.attribute("png:compressionLevel", 1);
        spec.attribute("png:filter", kPngFilterNone);
        spec.attribute("compression", "rle");  // Z_RLE
    }
    if (!out->set_ioproxy(&proxy) || !out->open("preview.png", spec) ||
        !out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) || !out->close())
        throw std::runtime_error("cannot encode PNG: " + oiioError(out.get()));
    out.reset();
    return bytes;
}

void writePng(const fs::path& path, const Image& image, float exposureStops) {
    std::vector<uint8_t> bytes;
    try {
        bytes = encodePng(image, exposureStops);
    } catch (const std::exception& e) {
        throw std::runtime_error("cannot write PNG " + quoted(path) + ": " + e.what());
    }
    writeAtomically(path, "PNG", [&](const fs::path& tmp) -> std::string {
        std::FILE* f = std::fopen(tmp.c_str(), "wb");
        if (!f) return std::error_code(errno, std::generic_category()).message();
        const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
        const int err = errno;
        if (std::fclose(f) != 0 || !ok)
            return "write failed: " +
                   std::error_code(ok ? errno : err, std::generic_category()).message();
        return {};
    });
}

float autoExposure(const Image& image) {
    std::vector<float> lum;
    lum.reserve(size_t(image.width) * image.height);
    for (size_t i = 0; i + 2 < image.rgb.size(); i += 3) {
        const float l = luminance({image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]});
        if (l > 0 && std::isfinite(l)) lum.push_back(l);
    }
    if (lum.empty()) return 0;
    const size_t k = size_t(0.99 * double(lum.size() - 1));
    std::nth_element(lum.begin(), lum.begin() + k, lum.end());
    return float(std::log2(0.9 / double(lum[k])));
}

}  // namespace partita
