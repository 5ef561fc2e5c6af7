#include "exr_header.h"

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
    HeaderWalk(uint64_t size, ReadAt read) : size_(size), read_(std::move(read)) {}

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

    /// One header's attributes, up to its terminating empty name (or where the file ends).
    std::string header(uint64_t& at) {
        std::string attribute, type;
        for (;;) {
            // Truncated or malformed: OpenEXR refuses that itself, without a large allocation.
            if (!name(at, attribute) || attribute.empty()) return {};
            if (!name(at, type)) return {};
            uint32_t size = 0;
            if (!readU32(at, size)) return {};
            at += 4;
            if (int32_t(size) < 0 || size > size_ - at)
                return "header attribute '" + attribute + "' claims " + std::to_string(size) +
                       " bytes, more than the file holds";
            at += size;
        }
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
};

}  // namespace

std::string exrHeaderProblem(std::span<const uint8_t> bytes) {
    return HeaderWalk(bytes.size(),
                      [&](uint64_t offset, size_t n, uint8_t* out) {
                          if (offset > bytes.size() || n > bytes.size() - offset) return false;
                          std::memcpy(out, bytes.data() + offset, n);
                          return true;
                      })
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
