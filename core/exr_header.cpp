#include "exr_header.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <functional>

namespace partita {

namespace {

constexpr uint32_t kExrMagic = 20000630;  // 76 2f 31 01
constexpr uint32_t kMultipartFlag = 0x1000;
constexpr size_t kMaxNameBytes = 256;  // long names are at most 255 characters

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

    /// What opening a scanline file makes OpenEXR allocate, from one header's attributes.
    struct Layout {
        int64_t width = 0, height = 0;
        uint64_t bytesPerPixel = 0;
        uint64_t linesPerBlock = 1;  // rows one compressed block holds
    };

    /// One header's attributes, up to its terminating empty name (or where the file ends).
    std::string header(uint64_t& at) {
        std::string attribute, type;
        Layout layout;
        for (;;) {
            // Truncated or malformed: OpenEXR refuses that itself, without a large allocation.
            if (!name(at, attribute)) return {};
            if (attribute.empty()) return openCost(layout);
            if (!name(at, type)) return {};
            uint32_t size = 0;
            if (!readU32(at, size)) return {};
            at += 4;
            if (int32_t(size) < 0 || size > size_ - at)
                return "header attribute '" + attribute + "' claims " + std::to_string(size) +
                       " bytes, more than the file holds";
            note(attribute, type, at, size, layout);
            at += size;
        }
    }

    /// Reads the attributes the allocation depends on: the data window, the channels and the
    /// compression (OpenEXR's block heights per compression: NO, RLE, ZIPS 1; ZIP, PXR24 16;
    /// PIZ, B44, B44A, DWAA 32; DWAB 256).
    void note(const std::string& attribute, const std::string& type, uint64_t at, uint32_t size,
              Layout& layout) {
        if (attribute == "dataWindow" && type == "box2i" && size == 16) {
            uint32_t box[4];
            for (int i = 0; i < 4; ++i)
                if (!readU32(at + 4 * uint64_t(i), box[i])) return;
            layout.width = int64_t(int32_t(box[2])) - int32_t(box[0]) + 1;
            layout.height = int64_t(int32_t(box[3])) - int32_t(box[1]) + 1;
        } else if (attribute == "compression" && size == 1) {
            uint8_t c = 0;
            if (!read_(at, 1, &c)) return;
            static const uint64_t kLines[] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
            layout.linesPerBlock = c < 10 ? kLines[c] : 256;
        } else if (attribute == "channels" && type == "chlist") {
            // name, pixel type (int32: 1 half, else 4 bytes), pLinear + 3 reserved, x/y sampling
            uint64_t p = at, end = at + size;
            std::string channel;
            layout.bytesPerPixel = 0;
            while (p < end && name(p, channel) && !channel.empty()) {
                uint32_t pixelType = 0;
                if (!readU32(p, pixelType)) return;
                layout.bytesPerPixel += pixelType == 1 ? 2 : 4;
                p += 16;
            }
        }
    }

    /// The line buffers and the line offsets OpenEXR allocates when it opens the file.
    std::string openCost(const Layout& l) const {
        if (l.width <= 0 || l.height <= 0) return {};  // OpenEXR refuses an empty window itself
        const double buffers = double(l.width) * double(l.bytesPerPixel) * double(l.linesPerBlock);
        const double offsets = double(l.height) / double(l.linesPerBlock) * 8;
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
