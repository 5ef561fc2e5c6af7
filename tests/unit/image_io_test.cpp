// Tests of EXR/PNG reading and writing (core/image_io).
#include <gtest/gtest.h>
#include <unistd.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <tuple>

#include "exr_header.h"
#include "image_io.h"

namespace partita {
namespace {

namespace fs = std::filesystem;

/// A fresh, empty folder per test, removed afterwards.
class ImageIoTest : public ::testing::Test {
  protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               ("partita-image-io-" + std::to_string(::getpid()) + "-" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    /// Names of the files in the test's folder.
    std::vector<std::string> listing() const {
        std::vector<std::string> out;
        for (const auto& e : fs::directory_iterator(dir_))
            out.push_back(e.path().filename().string());
        std::sort(out.begin(), out.end());
        return out;
    }
    fs::path dir_;
};

Image randomImage(int w, int h, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> d(0.0f, 1.0f);
    Image img(w, h);
    for (float& v : img.rgb) v = d(rng) * std::exp2(float(int(rng() % 40) - 20));  // wide range
    return img;
}

bool bytewiseEqual(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
           (a.rgb.empty() ||  // memcmp of null pointers is undefined, even for 0 bytes
            std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0);
}

/// Decode an 8-bit image with OIIO, independently of image_io.
std::vector<uint8_t> readBytes(std::unique_ptr<OIIO::ImageInput> in, int& w, int& h, int& nch) {
    EXPECT_TRUE(in) << OIIO::geterror();
    if (!in) return {};
    w = in->spec().width;
    h = in->spec().height;
    nch = in->spec().nchannels;
    std::vector<uint8_t> px(size_t(w) * h * nch);
    EXPECT_TRUE(in->read_image(0, 0, 0, nch, OIIO::TypeDesc::UINT8, px.data())) << in->geterror();
    return px;
}

TEST_F(ImageIoTest, ExrRoundTripIsBitExact) {
    LayeredImage img;
    img.combined = randomImage(19, 11, 1);
    img.combined.rgb[0] = 0.0f;
    img.combined.rgb[1] = std::numeric_limits<float>::denorm_min();
    img.combined.rgb[2] = 3.0e38f;  // beyond half range: FLOAT channels are needed
    img.combined.rgb[3] = -1.5f;
    // Names chosen so that EXR's alphabetical channel order differs from the layer order.
    img.layers.push_back({"LSDE", randomImage(19, 11, 2)});
    img.layers.push_back({"LDE", randomImage(19, 11, 3)});
    img.layers.push_back({"other", randomImage(19, 11, 4)});
    const std::map<std::string, std::string> meta = {
        {"partita:algorithm", "guided"},
        {"partita:parameters",
         std::string(200, 'x') + "{\"radius\": 0.05}"},  // longer than 64 chars
        {"partita:seed", "42"}};
    const fs::path path = dir_ / "result.exr";
    writeExr(path, img, meta);

    std::map<std::string, std::string> readMeta;
    const LayeredImage back = readExr(path, &readMeta);
    EXPECT_TRUE(bytewiseEqual(back.combined, img.combined));
    ASSERT_EQ(back.layers.size(), img.layers.size());
    for (size_t i = 0; i < img.layers.size(); ++i) {
        EXPECT_EQ(back.layers[i].name, img.layers[i].name);
        EXPECT_TRUE(bytewiseEqual(back.layers[i].image, img.layers[i].image)) << img.layers[i].name;
    }
    for (const auto& [k, v] : meta) EXPECT_EQ(readMeta[k], v) << k;
    EXPECT_EQ(readMeta.count("partita:layers"), 0u);
    EXPECT_EQ(readExr(path).layers.size(), 3u);

    // What other tools see: float channels with layered names.
    auto in = OIIO::ImageInput::open(path.string());
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().nchannels, 12);
    EXPECT_EQ(in->spec().format, OIIO::TypeDesc::FLOAT);
    bool hasLayerChannel = false;
    for (const auto& n : in->spec().channelnames) hasLayerChannel |= (n == "LSDE.G");
    EXPECT_TRUE(hasLayerChannel);
}

TEST_F(ImageIoTest, ExrWithoutLayers) {
    LayeredImage img;
    img.combined = randomImage(4, 3, 7);
    const fs::path path = dir_ / "plain.exr";
    writeExr(path, img);
    const LayeredImage back = readExr(path);
    EXPECT_TRUE(bytewiseEqual(back.combined, img.combined));
    EXPECT_TRUE(back.layers.empty());
}

TEST_F(ImageIoTest, ASizeLimitIsCheckedFromTheHeaderAndHeadersReadFromBytes) {
    LayeredImage img;
    img.combined = randomImage(8, 4, 3);
    const fs::path path = dir_ / "limit.exr";
    writeExr(path, img);
    EXPECT_NO_THROW(readExr(path, nullptr, 32));
    try {
        readExr(path, nullptr, 31);
        ADD_FAILURE() << "an image over the limit was read";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("8 x 4 pixels are more than the 31 allowed"),
                  std::string::npos)
            << e.what();
    }
    std::ifstream in(path, std::ios::binary);
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), {});
    ImageHeader h = readImageHeader(bytes, "sky.exr");
    EXPECT_EQ(h.width, 8);
    EXPECT_EQ(h.height, 4);
    EXPECT_EQ(h.channels, 3);
    // A Radiance header alone is enough to know the size.
    std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4096 +X 8192\n";
    h = readImageHeader({reinterpret_cast<const uint8_t*>(hdr.data()), hdr.size()}, "a/sky.hdr");
    EXPECT_EQ(h.pixels(), size_t(8192) * 4096);
    std::string junk = "not an image";
    EXPECT_THROW(
        readImageHeader({reinterpret_cast<const uint8_t*>(junk.data()), junk.size()}, "sky.exr"),
        std::runtime_error);
}

/// One EXR attribute: name, type, size, value.
void exrAttribute(std::vector<uint8_t>& b, const std::string& name, const std::string& type,
                  const std::vector<uint8_t>& value) {
    b.insert(b.end(), name.c_str(), name.c_str() + name.size() + 1);
    b.insert(b.end(), type.c_str(), type.c_str() + type.size() + 1);
    for (int i = 0; i < 4; ++i) b.push_back(uint8_t(value.size() >> (8 * i)));
    b.insert(b.end(), value.begin(), value.end());
}

std::vector<uint8_t> le32(std::initializer_list<int32_t> values) {
    std::vector<uint8_t> out;
    for (int32_t v : values)
        for (int i = 0; i < 4; ++i) out.push_back(uint8_t(uint32_t(v) >> (8 * i)));
    return out;
}

// Found by tests/fuzz/fuzz_environment_image: a 750-byte file whose data window was 268 million
// pixels wide made OpenEXR allocate a 1 GiB line buffer while readImageHeader opened it.
TEST_F(ImageIoTest, AnExrWhoseDataWindowWouldNeedGigabytesToOpenIsRefusedFirst) {
    auto exr = [](int32_t width, int32_t height) {
        std::vector<uint8_t> b = {0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0};
        std::vector<uint8_t> channel = {'Y', 0};
        for (uint8_t x : le32({2, 0, 1, 1})) channel.push_back(x);  // float, pLinear 0, 1 x 1
        channel.push_back(0);
        exrAttribute(b, "channels", "chlist", channel);
        exrAttribute(b, "compression", "compression", {0});
        exrAttribute(b, "dataWindow", "box2i", le32({0, 0, width - 1, height - 1}));
        b.push_back(0);
        return b;
    };
    try {
        readImageHeader(exr(268459369, 1), "sky.exr");
        ADD_FAILURE() << "a 268 million pixel wide EXR was opened";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("data window"), std::string::npos) << e.what();
    }
    EXPECT_THROW(readImageHeader(exr(1, 1 << 30), "sky.exr"), std::runtime_error);  // offsets
    // Within the bound the walk leaves the file to OpenEXR (which refuses this one: it lacks
    // attributes), and real files read as before (the tests above).
    try {
        readImageHeader(exr(16384, 8192), "sky.exr");
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()).find("data window"), std::string::npos) << e.what();
    }
}

/// readImageHeader's error for `bytes` as an .exr; "" when it reads them.
std::string headerError(const std::vector<uint8_t>& bytes) {
    try {
        readImageHeader(bytes, "sky.exr");
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return {};
}

// Found by tests/fuzz/fuzz_environment_image (with -malloc_limit_mb): OpenEXR 3.1 reads a value
// of a type it knows at the type's own size, whatever the attribute's size field says, and
// reads the header on from there; a walk that skipped by the size field did not see a data
// window OpenEXR then opened (32 MiB and 846 MB allocated for files of 469 and 561 bytes).
TEST_F(ImageIoTest, AnExrHeaderIsReadAsOpenExrReadsIt) {
    auto start = [] { return std::vector<uint8_t>{0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0}; };
    std::vector<uint8_t> list = {'Y', 0};  // one channel: float, pLinear 0, 1 x 1; the end
    for (uint8_t x : le32({2, 0, 1, 1})) list.push_back(x);
    list.push_back(0);
    auto channels = [&list](std::vector<uint8_t>& b) {
        exrAttribute(b, "channels", "chlist", list);
    };
    std::vector<uint8_t> wide;  // a data window 268 million pixels wide, as attribute bytes
    exrAttribute(wide, "dataWindow", "box2i", le32({0, 0, (1 << 28) - 1, 0}));

    // A compression whose size field also covers the data window after its one byte.
    std::vector<uint8_t> b = start();
    channels(b);
    std::vector<uint8_t> compression = {0};  // NO_COMPRESSION
    compression.insert(compression.end(), wide.begin(), wide.end());
    exrAttribute(b, "compression", "compression", compression);
    b.push_back(0);
    EXPECT_NE(headerError(b).find("data window"), std::string::npos) << headerError(b);

    // A channel list whose size field is short of the list: OpenEXR reads to its empty name.
    b = start();
    std::vector<uint8_t> shortList(list.begin(), list.begin() + 1);  // size field: 1
    exrAttribute(b, "channels", "chlist", shortList);
    b.insert(b.end(), list.begin() + 1, list.end());
    b.insert(b.end(), wide.begin(), wide.end());
    exrAttribute(b, "compression", "compression", {0});
    b.push_back(0);
    EXPECT_NE(headerError(b).find("data window"), std::string::npos) << headerError(b);

    // A header cut short after its data window: OpenEXR gets as far as opening it.
    b = start();
    channels(b);
    b.insert(b.end(), wide.begin(), wide.end());
    b.push_back('x');  // a name that never ends
    EXPECT_NE(headerError(b).find("data window"), std::string::npos) << headerError(b);

    // A preview image OpenEXR would allocate before reading (40000 x 40000 x 4 bytes).
    b = start();
    channels(b);
    exrAttribute(b, "preview", "preview", le32({40000, 40000}));
    b.push_back(0);
    EXPECT_NE(headerError(b).find("preview image"), std::string::npos) << headerError(b);

    // Tiles of one pixel over a window of 2^28 pixels: a tile offset table of 2 GiB.
    b = start();
    channels(b);
    exrAttribute(b, "dataWindow", "box2i", le32({0, 0, (1 << 14) - 1, (1 << 14) - 1}));
    std::vector<uint8_t> tiles = le32({1, 1});
    tiles.push_back(0);  // ONE_LEVEL
    exrAttribute(b, "tiles", "tiledesc", tiles);
    b.push_back(0);
    EXPECT_NE(headerError(b).find("data window"), std::string::npos) << headerError(b);
}

TEST_F(ImageIoTest, OnlyTheReaderOfTheExtensionParsesAnImage) {
    // An uploaded image is untrusted: a file named .exr that is not EXR must not reach every
    // other format reader OpenImageIO has (its default), only be refused.
    std::string hdr =
        "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8\n" + std::string(4 * 8 * 4, 'x');
    std::span<const uint8_t> bytes(reinterpret_cast<const uint8_t*>(hdr.data()), hdr.size());
    EXPECT_EQ(readImageHeader(bytes, "sky.hdr").pixels(), size_t(32));
    EXPECT_THROW(readImageHeader(bytes, "sky.exr"), std::runtime_error);
    const fs::path file = dir_ / "radiance.exr";
    std::ofstream(file, std::ios::binary) << hdr;
    EXPECT_THROW(readExr(file, nullptr, 0), std::runtime_error);
}

/// An EXR header of one string attribute whose size field claims `claimed` bytes, followed by
/// a few bytes of value: what OpenEXR 3.1 would allocate before noticing the file is short.
std::vector<uint8_t> exrWithAStringClaiming(uint32_t claimed) {
    std::vector<uint8_t> b = {0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0};
    for (const char* s : {"comments", "string"}) b.insert(b.end(), s, s + std::strlen(s) + 1);
    for (int i = 0; i < 4; ++i) b.push_back(uint8_t(claimed >> (8 * i)));
    b.insert(b.end(), 16, 'x');
    return b;
}

// Found by tests/fuzz/fuzz_environment_image: a 40-byte upload made readImageHeader allocate
// and clear what the attribute claimed (up to 2 GiB) inside OpenEXR.
TEST_F(ImageIoTest, AnExrAttributeLargerThanTheFileIsRefusedBeforeOpenExrReadsIt) {
    const std::vector<uint8_t> bomb = exrWithAStringClaiming(1u << 30);
    const std::string want = "attribute 'comments' claims 1073741824 bytes, more than the file";
    try {
        readImageHeader(bomb, "sky.exr");
        ADD_FAILURE() << "read";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(want), std::string::npos) << e.what();
    }
    const fs::path path = dir_ / "bomb.exr";
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(bomb.data()), std::streamsize(bomb.size()));
    try {
        readExr(path, nullptr, 1 << 16);
        ADD_FAILURE() << "read";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(want), std::string::npos) << e.what();
    }
    // A claim that fits is left to OpenEXR; a real file passes.
    EXPECT_EQ(exrHeaderProblem(exrWithAStringClaiming(16)), "");
    LayeredImage img;
    img.combined = randomImage(4, 2, 5);
    writeExr(dir_ / "ok.exr", img, {{"note", "a string attribute"}});
    EXPECT_EQ(exrHeaderProblem(dir_ / "ok.exr"), "");
}

TEST_F(ImageIoTest, ExrRejectsMismatchedLayers) {
    LayeredImage img;
    img.combined = Image(4, 4);
    img.layers.push_back({"LDE", Image(4, 5)});
    EXPECT_THROW(writeExr(dir_ / "bad.exr", img), std::runtime_error);
    img.layers[0].image = Image(4, 4);
    img.layers.push_back({"LDE", Image(4, 4)});
    EXPECT_THROW(writeExr(dir_ / "bad.exr", img), std::runtime_error);
    EXPECT_TRUE(listing().empty());
}

TEST_F(ImageIoTest, ReadsPlainRgbAndRgbaExr) {
    const int w = 5, h = 4;
    for (int nch : {3, 4}) {
        std::vector<float> px(size_t(w) * h * nch);
        for (size_t i = 0; i < px.size(); ++i) px[i] = 0.125f * float(i);
        const fs::path path = dir_ / ("plain" + std::to_string(nch) + ".exr");
        auto out = OIIO::ImageOutput::create(path.string());
        ASSERT_TRUE(out);
        OIIO::ImageSpec spec(w, h, nch, OIIO::TypeDesc::FLOAT);
        ASSERT_TRUE(out->open(path.string(), spec)) << out->geterror();
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
        ASSERT_TRUE(out->close());

        const LayeredImage img = readExr(path);
        ASSERT_EQ(img.combined.width, w);
        ASSERT_EQ(img.combined.height, h);
        EXPECT_TRUE(img.layers.empty());
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float* p = &px[(size_t(y) * w + x) * nch];
                EXPECT_EQ(img.combined.at(x, y), Rgb(p[0], p[1], p[2]))
                    << nch << " channels, " << x << "," << y;
            }
    }
}

TEST_F(ImageIoTest, ReadingAMissingFileThrows) {
    try {
        readExr(dir_ / "missing.exr");
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("missing.exr"), std::string::npos) << e.what();
    }
}

TEST_F(ImageIoTest, PngEncodesKnownSrgbValues) {
    // Hand-computed 8-bit sRGB codes, round(255 * OETF(v)):
    //   0          -> 0
    //   0.0031308  -> 12.92 * 0.0031308 = 0.040450 -> 10.31 -> 10 (end of the linear segment)
    //   0.5        -> 1.055 * 0.5^(1/2.4) - 0.055 = 1.055 * 0.749154 - 0.055 = 0.735357
    //                 -> 187.52 -> 188
    //   1          -> 255
    //   2          -> clamped to 1 -> 255
    //   0.25 at +1 stop is 0.5 -> 188; 0.02 -> 1.055 * 0.02^(1/2.4) - 0.055 = 1.055 * 0.195928 -
    //   0.055
    //                 = 0.151704 -> 38.68 -> 39
    const float inputs[] = {0.0f, 0.0031308f, 0.5f, 1.0f, 2.0f, -1.0f, 0.02f};
    const uint8_t expected[] = {0, 10, 188, 255, 255, 0, 39};
    const int n = int(std::size(inputs));
    Image img(n, 2);
    for (int x = 0; x < n; ++x) {
        img.set(x, 0, Rgb(inputs[x]));
        img.set(x, 1, Rgb(inputs[x] * 0.5f));  // row 1 is written at +1 stop below
    }
    const fs::path path = dir_ / "known.png";
    writePng(path, img);
    int w = 0, h = 0, nch = 0;
    std::vector<uint8_t> px = readBytes(OIIO::ImageInput::open(path.string()), w, h, nch);
    ASSERT_EQ(w, n);
    ASSERT_EQ(h, 2);
    ASSERT_EQ(nch, 3);
    for (int x = 0; x < n; ++x)
        for (int k = 0; k < 3; ++k)
            EXPECT_EQ(int(px[size_t(x) * 3 + k]), int(expected[x])) << "input " << inputs[x];

    writePng(path, img, 1.0f);
    px = readBytes(OIIO::ImageInput::open(path.string()), w, h, nch);
    for (int x = 0; x < n; ++x)
        EXPECT_EQ(int(px[(size_t(n) + x) * 3]), int(expected[x])) << "input " << inputs[x];
}

TEST(Png, Srgb8MatchesTheExactCurve) {
    // The table-driven encoder against the formula evaluated in double, over a fine sweep.
    auto reference = [](double v) {
        v = std::clamp(v, 0.0, 1.0);
        const double e = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
        return int(std::floor(255.0 * e + 0.5));
    };
    for (int i = 0; i <= 100000; ++i) {
        const float v = float(i) / 90000.0f;  // up to 1.11: also checks the clamp
        ASSERT_EQ(int(encodeSrgb8(v)), reference(v)) << v;
    }
    EXPECT_EQ(encodeSrgb8(std::numeric_limits<float>::quiet_NaN()), 0);
    EXPECT_EQ(encodeSrgb8(std::numeric_limits<float>::infinity()), 255);
    EXPECT_EQ(encodeSrgb8(-std::numeric_limits<float>::infinity()), 0);
}

TEST_F(ImageIoTest, EncodePngMatchesWritePng) {
    Image img = randomImage(23, 9, 5);
    for (float& v : img.rgb) v = std::min(v * 1e5f, 3.0f);
    const std::vector<uint8_t> bytes = encodePng(img, -0.5f);
    const uint8_t signature[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    ASSERT_GE(bytes.size(), sizeof(signature));
    EXPECT_EQ(std::memcmp(bytes.data(), signature, sizeof(signature)), 0);

    const fs::path path = dir_ / "preview.png";
    writePng(path, img, -0.5f);
    int w1 = 0, h1 = 0, c1 = 0, w2 = 0, h2 = 0, c2 = 0;
    const std::vector<uint8_t> fromFile =
        readBytes(OIIO::ImageInput::open(path.string()), w1, h1, c1);

    OIIO::Filesystem::IOMemReader mem(bytes.data(), bytes.size());
    OIIO::ImageSpec config;
    OIIO::Filesystem::IOProxy* proxy = &mem;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    const std::vector<uint8_t> fromMemory =
        readBytes(OIIO::ImageInput::open("preview.png", &config), w2, h2, c2);
    EXPECT_EQ(w1, 23);
    EXPECT_EQ(h1, 9);
    EXPECT_EQ(w2, w1);
    EXPECT_EQ(h2, h1);
    EXPECT_EQ(c2, c1);
    EXPECT_EQ(fromMemory, fromFile);
    size_t i = 0;
    for (float v : img.rgb) ASSERT_EQ(fromFile[i++], encodeSrgb8(v * std::exp2(-0.5f)));
}

/// Decode PNG bytes held in memory with OIIO.
std::vector<uint8_t> decodePng(const std::vector<uint8_t>& bytes, int& w, int& h, int& nch) {
    OIIO::Filesystem::IOMemReader mem(bytes.data(), bytes.size());
    OIIO::ImageSpec config;
    OIIO::Filesystem::IOProxy* proxy = &mem;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    return readBytes(OIIO::ImageInput::open("preview.png", &config), w, h, nch);
}

TEST(Png, FastModeDecodesToTheSamePixelsAsTheDefault) {
    // Render-like rows (smooth, noisy, black) and every special value; two sizes and exposures.
    for (auto [w, h, exposure] : {std::tuple{97, 61, -0.5f}, std::tuple{320, 240, 2.0f}}) {
        Image img = randomImage(w, h, uint32_t(w));
        for (int y = 0; y < h; y += 3)
            for (int x = 0; x < w; ++x)
                img.set(x, y, y % 2 ? Rgb(0.0f) : Rgb(float(x) / float(w), 0.25f, 0.0f));
        const float specials[] = {std::numeric_limits<float>::quiet_NaN(),
                                  std::numeric_limits<float>::infinity(),
                                  -std::numeric_limits<float>::infinity(),
                                  -1.0f,
                                  0.0f,
                                  std::numeric_limits<float>::denorm_min(),
                                  1.0f,
                                  1e30f};
        for (size_t i = 0; i < std::size(specials); ++i) img.rgb[i * 7] = specials[i];

        const std::vector<uint8_t> normal = encodePng(img, exposure);
        const std::vector<uint8_t> fast = encodePng(img, exposure, PngOptions{.fast = true});
        EXPECT_NE(fast, normal) << "the fast mode compresses differently";
        int w1 = 0, h1 = 0, c1 = 0, w2 = 0, h2 = 0, c2 = 0;
        const std::vector<uint8_t> a = decodePng(normal, w1, h1, c1);
        const std::vector<uint8_t> b = decodePng(fast, w2, h2, c2);
        ASSERT_EQ(w1, w);
        ASSERT_EQ(h1, h);
        ASSERT_EQ(c1, 3);
        ASSERT_EQ(w2, w);
        ASSERT_EQ(h2, h);
        ASSERT_EQ(c2, 3);
        ASSERT_EQ(a, b);
        size_t i = 0;
        for (float v : img.rgb) ASSERT_EQ(b[i++], encodeSrgb8(v * std::exp2(exposure))) << i;
    }
}

TEST(Png, Srgb8StepsExactlyAtTheCodeBoundaries) {
    // The table-driven encoder at the floats next to every boundary between two codes (where a
    // table bucket is ambiguous), against the curve evaluated in double.
    auto reference = [](double v) {
        const double e = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
        return int(std::floor(255.0 * e + 0.5));
    };
    for (int b = 1; b <= 255; ++b) {
        const double e = (b - 0.5) / 255.0;
        const float t = float(e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4));
        float v = t;
        for (int k = 0; k < 4; ++k) v = std::nextafter(v, 0.0f);
        for (int k = 0; k < 9; ++k, v = std::nextafter(v, 2.0f)) {
            ASSERT_LT(v, 1.0f);
            ASSERT_EQ(int(encodeSrgb8(v)), reference(v)) << b << " " << v;
        }
    }
}

TEST_F(ImageIoTest, WritingIntoAMissingDirectoryThrowsAClearError) {
    LayeredImage img;
    img.combined = Image(2, 2);
    const fs::path missing = dir_ / "no-such-dir" / "out.exr";
    for (int which = 0; which < 2; ++which) {
        try {
            if (which == 0)
                writeExr(missing, img);
            else
                writePng(missing.parent_path() / "out.png", img.combined);
            FAIL() << "no exception";
        } catch (const std::runtime_error& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find("no-such-dir"), std::string::npos) << msg;
            EXPECT_NE(msg.find("does not exist"), std::string::npos) << msg;
        }
    }
    EXPECT_FALSE(fs::exists(dir_ / "no-such-dir"));
}

TEST_F(ImageIoTest, AtomicWriteLeavesNoTemporaryFile) {
    LayeredImage img;
    img.combined = randomImage(8, 8, 6);
    img.layers.push_back({"LDE", img.combined});
    writeExr(dir_ / "a.exr", img);
    writePng(dir_ / "a.png", img.combined);
    EXPECT_EQ(listing(), (std::vector<std::string>{"a.exr", "a.png"}));

    // Overwriting replaces the file, still without leftovers.
    img.combined = randomImage(8, 8, 7);
    writeExr(dir_ / "a.exr", img);
    writePng(dir_ / "a.png", img.combined);
    EXPECT_EQ(listing(), (std::vector<std::string>{"a.exr", "a.png"}));
    EXPECT_TRUE(bytewiseEqual(readExr(dir_ / "a.exr").combined, img.combined));

    // A failed write (the target is a folder) leaves nothing either.
    fs::create_directory(dir_ / "sub.exr");
    EXPECT_THROW(writeExr(dir_ / "sub.exr", img), std::runtime_error);
    EXPECT_EQ(listing(), (std::vector<std::string>{"a.exr", "a.png", "sub.exr"}));
}

TEST(ImageIo, AutoExposureMapsThe99thPercentileTo09) {
    // 1000 pixels of luminance 1..1000 (grey, so luminance == value) and zeros, which are
    // ignored: the 99th percentile is ~990.
    Image img(1000, 2);
    for (int x = 0; x < 1000; ++x) img.set(x, 0, Rgb(float(x + 1)));
    const float ev = autoExposure(img);
    const float p99 = 0.9f / std::exp2(ev);
    EXPECT_GT(p99, 985.0f);
    EXPECT_LT(p99, 995.0f);
    EXPECT_EQ(autoExposure(Image(4, 4)), 0.0f);

    // Scaling the image by 8 lowers the exposure by 3 stops.
    Image brighter = img;
    for (float& v : brighter.rgb) v *= 8.0f;
    EXPECT_NEAR(autoExposure(brighter), ev - 3.0f, 1e-5f);
}

}  // namespace
}  // namespace partita
