// A check of an OpenEXR file's header before OpenEXR reads it (issue #25; found by
// tests/fuzz/fuzz_environment_image): OpenEXR 3.1 allocates what an attribute's size field
// claims before reading its value, so a 100-byte file whose string attribute claims 2 GiB made
// readImageHeader allocate and clear 2 GiB. This walks the header(s) itself, reading names and
// size fields only, and refuses any attribute that claims more bytes than the file holds.
// Opening a scanline file, OpenEXR also allocates its line buffers (lines per compression block
// x width x bytes per pixel) and its table of line offsets (one per block) from the data window
// alone: a 750-byte file claiming a data window 268 million pixels wide made it allocate 1 GiB
// (found by the same fuzzer). Both are refused above kMaxExrOpenBytes. The walk reads values as
// OpenEXR 3.1 does: a type it knows at its own size whatever the size field says (the header
// goes on from there), a channel list to its empty name, a header cut short as far as it goes;
// tiled files' tile buffers and offset tables and preview images count too.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace partita {

/// The most a header may make OpenEXR allocate when the file is opened (line buffers, line
/// offsets). A result 1920 wide with 1024 layers (ZIP: 16 lines of 1920 x 1024 x 12 B) needs
/// 360 MiB and is read; an 8192-wide one of 1024 layers (1.5 GiB) is refused.
inline constexpr uint64_t kMaxExrOpenBytes = uint64_t(512) << 20;

/// "" when `bytes` are not an OpenEXR file (other formats are not its business) or every
/// attribute of its header(s) fits in them and opening it costs at most `maxOpenBytes`; else
/// why the file is refused, one line. (A smaller `maxOpenBytes`: the fuzz target's, so that
/// its runs do not spend their time clearing buffers of hundreds of MiB.)
std::string exrHeaderProblem(std::span<const uint8_t> bytes,
                             uint64_t maxOpenBytes = kMaxExrOpenBytes);

/// The same for a file, reading only its header. "" when it cannot be opened.
std::string exrHeaderProblem(const std::filesystem::path& file);

}  // namespace partita
