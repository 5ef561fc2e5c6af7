#include "exr_header.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>

namespace partita {

namespace {

constexpr uint32_t kExrMagic = 20000630;  // 76 2f 31 01
constexpr uint32_t kMultipartFlag = 0x1000;
constexpr size_t kMaxNameBytes = 256;  // long names are at most 255 characters

/// Bytes OpenEXR 3.1 reads for a value of a type it knows whose size does not depend on the
/// data (TypedAttribute<T>::readValueFrom); 0 for the others (strings, vectors, types it does
/// not know: read by their size field; channel lists and previews: read apart).
uint64_t fixedValueBytes(const std::string& type) {
    static const std::pair<const char*, uint64_t> kSizes[] = {
        {"box2i", 16},      {"box2f", 16},
        {"compression", 1}, {"lineOrder", 1},
        {"envmap", 1},      {"deepImageState", 1},
        {"int", 4},         {"float", 4},
        {"double", 8},      {"v2i", 8},
        {"v2f", 8},         {"v2d", 16},
        {"v3i", 12},        {"v3f", 12},
        {"v3d", 24},        {"m33f", 36},
        {"m33d", 72},       {"m44f", 64},
        {"m44d", 128},      {"chromaticities", 32},
        {"keycode", 28},    {"timecode", 8},
        {"rational", 8},    {"tiledesc", 9}};
    for (const auto& [name, bytes] : kSizes)
        if (type == name) return bytes;
    return 0;
}

/// Reads n bytes at an offset; false past the end.
using ReadAt = std::function<bool(uint64_t offset, size_t n, uint8_t* out)>;

/// The walk over the header(s) of an EXR of `size` bytes (see exr_header.h).
class HeaderWalk {
  public:
    HeaderWalk(uint64_t size, ReadAt read, uint64_t maxOpenBytes = kMaxExrOpenBytes)
        : size_(size), read_(std::move(read)), maxOpenBytes_(maxOpenBytes) {}

    std::string problem() {
        uint32_t magic = 0, version = 0;
        if (!readU32(0, magic) || magic != kExrMagic) return {};
        if (!readU32(4, version)) return {};
        uint64_t at = 8;
        const bool multipart = (version & kMultipartFlag) != 0;
        do {
            if (std::string why = header(at); !why.empty()) return why;
        } while (multipart && !endOfHeaders(at));
        return {};
    }

  private:
    bool readU32(uint64_t at, uint32_t& value) {
        uint8_t b[4];
        if (!read_(at, 4, b)) return false;
        std::memcpy(&value, b, 4);
        return true;
    }

    /// A NUL-terminated name at `at` (advanced past it); false when it does not end in time.
    bool name(uint64_t& at, std::string& out) {
        out.clear();
        uint8_t c = 0;
        for (size_t i = 0; i < kMaxNameBytes; ++i) {
            if (!read_(at++, 1, &c)) return false;
            if (c == 0) return true;
            out.push_back(char(c));
        }
        return false;
    }

    /// What opening the file makes OpenEXR allocate, from one header's attributes.
    struct Layout {
        int64_t width = 0, height = 0;
        uint64_t bytesPerPixel = 0;
        uint64_t linesPerBlock = 16;  // rows one compressed block holds (ZIP's, OpenEXR's default)
        uint64_t tileWidth = 0, tileHeight = 0;  // a tiled file's ("tiles"), else 0
        int levelMode = 0;                       // ONE_LEVEL, MIPMAP_LEVELS, RIPMAP_LEVELS
    };

    /// One header's attributes, up to its terminating empty name (or where the file ends).
    std::string header(uint64_t& at) {
        std::string attribute, type;
        Layout layout;
        for (;;) {
            // Truncated or malformed: OpenEXR should refuse that itself, but it reads some such
            // headers further than this walk (found by fuzz_environment_image: it opened one
            // and allocated 32 MiB for its line buffers), so what was read so far is checked.
            if (!name(at, attribute)) return openCost(layout);
            if (attribute.empty()) return openCost(layout);
            if (!name(at, type)) return openCost(layout);
            uint32_t size = 0;
            if (!readU32(at, size)) return openCost(layout);
            at += 4;
            if (int32_t(size) < 0 || size > size_ - at)
                return "header attribute '" + attribute + "' claims " + std::to_string(size) +
                       " bytes, more than the file holds";
            if (type == "chlist") {
                // OpenEXR 3.1 reads a channel list up to its empty name whatever the attribute's
                // size says, and reads the header on from there: so does this walk (found by
                // fuzz_environment_image: a list of size 19 that ran on, then a data window
                // this walk had skipped as the list's bytes).
                if (!channelList(at, attribute == "channels" ? &layout : nullptr))
                    return openCost(layout);
                continue;
            }
            if (type == "preview") {
                if (std::string why = preview(at, layout); !why.empty()) return why;
                continue;
            }
            note(attribute, type, at, layout);
            // A type OpenEXR knows is read at its own size, whatever the size field says, and
            // the header goes on from there (found by fuzz_environment_image: a compression of
            // size 17, then a data window this walk had skipped as its bytes).
            const uint64_t fixed = fixedValueBytes(type);
            at += fixed > 0 ? fixed : size;
        }
    }

    /// A preview image: width x height x 4 bytes that OpenEXR allocates (3.1 first compares them
    /// with the size field; a preview above the bound is refused here either way).
    std::string preview(uint64_t& at, Layout& layout) {
        uint32_t width = 0, height = 0;
        if (!readU32(at, width) || !readU32(at + 4, height)) return openCost(layout);
        const double bytes = double(width) * double(height) * 4;
        if (bytes > double(maxOpenBytes_))
            return "its preview image (" + std::to_string(width) + " x " + std::to_string(height) +
                   ") would need more memory to open than the " +
                   std::to_string(maxOpenBytes_ >> 20) + " MiB allowed";
        at += 8 + uint64_t(bytes);
        return {};
    }

    /// The channel list at `at` (advanced past its empty name), its channels' bytes added to
    /// `layout` when given: a repeated list adds to them (OpenEXR merges it into the first).
    /// false when it does not end.
    bool channelList(uint64_t& at, Layout* layout) {
        // name, pixel type (int32: 1 half, else 4 bytes), pLinear + 3 reserved, x/y sampling
        std::string channel;
        for (;;) {
            if (!name(at, channel)) return false;
            if (channel.empty()) return true;
            uint32_t pixelType = 0;
            if (!readU32(at, pixelType)) return false;
            if (layout) layout->bytesPerPixel += pixelType == 1 ? 2 : 4;
            at += 16;
        }
    }

    /// Reads the attributes the allocation depends on besides the channels: the data window, the
    /// tiles and the compression (OpenEXR's block heights per compression: NO, RLE, ZIPS 1; ZIP,
    /// PXR24 16; PIZ, B44, B44A, DWAA 32; DWAB 256).
    void note(const std::string& attribute, const std::string& type, uint64_t at, Layout& layout) {
        if (attribute == "dataWindow" && type == "box2i") {
            uint32_t box[4];
            for (int i = 0; i < 4; ++i)
                if (!readU32(at + 4 * uint64_t(i), box[i])) return;
            layout.width = int64_t(int32_t(box[2])) - int32_t(box[0]) + 1;
            layout.height = int64_t(int32_t(box[3])) - int32_t(box[1]) + 1;
        } else if (attribute == "tiles" && type == "tiledesc") {
            uint32_t tile[2];
            uint8_t mode = 0;
            if (!readU32(at, tile[0]) || !readU32(at + 4, tile[1]) || !read_(at + 8, 1, &mode))
                return;
            layout.tileWidth = tile[0];
            layout.tileHeight = tile[1];
            layout.levelMode = mode & 0xf;
        } else if (attribute == "compression" && type == "compression") {
            uint8_t c = 0;
            if (!read_(at, 1, &c)) return;
            static const uint64_t kLines[] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
            layout.linesPerBlock = c < 10 ? kLines[c] : 256;
        }
    }

    /// The line buffers and the line offsets OpenEXR allocates when it opens the file.
    std::string openCost(const Layout& l) const {
        if (l.width <= 0 || l.height <= 0) return {};  // OpenEXR refuses an empty window itself
        double buffers = double(l.width) * double(l.bytesPerPixel) * double(l.linesPerBlock);
        double offsets = double(l.height) / double(l.linesPerBlock) * 8;
        if (l.tileWidth > 0 || l.tileHeight > 0) {
            // A tiled file: a tile's buffer, and one offset a tile of every level (mipmaps add
            // a third, ripmaps three times the first level's tiles: counted as 4x).
            const double tw = double(std::max<uint64_t>(1, l.tileWidth)),
                         th = double(std::max<uint64_t>(1, l.tileHeight));
            buffers = std::max(buffers, tw * th * double(l.bytesPerPixel));
            const double tiles = std::ceil(double(l.width) / tw) * std::ceil(double(l.height) / th);
            offsets = std::max(offsets, tiles * 8 * (l.levelMode == 0 ? 1 : 4));
        }
        if (std::max(buffers, offsets) <= double(maxOpenBytes_)) return {};
        return "its data window (" + std::to_string(l.width) + " x " + std::to_string(l.height) +
               " pixels of " + std::to_string(l.bytesPerPixel) +
               " bytes) would need more memory to open than the " +
               std::to_string(maxOpenBytes_ >> 20) + " MiB allowed";
    }

    /// Multipart files end their list of headers with an empty one.
    bool endOfHeaders(uint64_t& at) {
        uint8_t c = 0;
        if (!read_(at, 1, &c)) return true;  // truncated: OpenEXR says so itself
        if (c != 0) return false;
        ++at;
        return true;
    }

    uint64_t size_;
    ReadAt read_;
    uint64_t maxOpenBytes_;
};

}  // namespace

std::string exrHeaderProblem(std::span<const uint8_t> bytes, uint64_t maxOpenBytes) {
    return HeaderWalk(
               bytes.size(),
               [&](uint64_t offset, size_t n, uint8_t* out) {
                   if (offset > bytes.size() || n > bytes.size() - offset) return false;
                   std::memcpy(out, bytes.data() + offset, n);
                   return true;
               },
               maxOpenBytes)
        .problem();
}

std::string exrHeaderProblem(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::error_code ec;
    const uint64_t size = std::filesystem::file_size(file, ec);
    if (!in || ec) return {};
    return HeaderWalk(size,
                      [&](uint64_t offset, size_t n, uint8_t* out) {
                          if (offset > size || n > size - offset) return false;
                          in.seekg(std::streamoff(offset));
                          return bool(in.read(reinterpret_cast<char*>(out), std::streamsize(n)));
                      })
        .problem();
}

}  // namespace partita
