// libFuzzer target for environment images (EXR, HDR) along the daemon's path: readImageHeader
// on the uploaded bytes at submission (server/validation.cpp), then readExr with a pixel limit
// from the file when the job runs (core/scene_environment.cpp). The first byte picks the file
// name's extension, which tells OpenImageIO the format. The contract: bad input throws
// std::runtime_error; anything else (another exception, a sanitizer report, a hang, memory
// beyond -rss_limit_mb) is a bug. OpenImageIO and OpenEXR are not instrumented: libFuzzer sees
// coverage of our code only, so its mutations explore their parsers blindly.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <span>
#include <stdexcept>
#include <string>

#include "exr_header.h"
#include "image_io.h"

namespace {

// Small bounds, the same checks as the daemon's (kMaxEnvironmentPixels, kMaxExrOpenBytes: 512
// MiB). What an input may allocate sets the rate: ASan serves a block over 128 KiB with a fresh
// mmap, so every such input paid page faults to clear its buffers (perf: 72% of the time in
// memset and its faults). With the daemon's open bound a run managed ~20 inputs a second, with
// 4 MiB and 65536 pixels ~300; with these, whose buffers stay under 128 KiB, see
// tests/fuzz/README.md. The parsers' code is the same for small and large images.
constexpr size_t kFuzzMaxPixels = size_t(1) << 12;
constexpr uint64_t kFuzzMaxOpenBytes = uint64_t(96) << 10;

std::filesystem::path scratchFile(const std::string& extension) {
    return std::filesystem::temp_directory_path() /
           ("partita-fuzz-env-" + std::to_string(getpid()) + extension);
}

void writeBytes(const std::filesystem::path& path, std::span<const uint8_t> bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    const std::string extension = (data[0] & 1) ? ".hdr" : ".exr";
    std::span<const uint8_t> bytes(data + 1, size - 1);
    // Costlier to open than the fuzz bound: skipped (the daemon refuses such a file above
    // kMaxExrOpenBytes by this same check, at submission; below it only memory is at stake).
    if (!partita::exrHeaderProblem(bytes, kFuzzMaxOpenBytes).empty()) return 0;
    try {
        partita::ImageHeader header = partita::readImageHeader(bytes, "environment" + extension);
        if (header.pixels() > kFuzzMaxPixels) return 0;  // refused at submission
    } catch (const std::runtime_error&) {
        // a file that cannot be read now fails the job when it runs: read it anyway below
    }
    const std::filesystem::path file = scratchFile(extension);
    writeBytes(file, bytes);
    try {
        partita::LayeredImage image = partita::readExr(file, nullptr, kFuzzMaxPixels);
        (void)image;
    } catch (const std::runtime_error&) {
        // expected for malformed input
    }
    return 0;
}
