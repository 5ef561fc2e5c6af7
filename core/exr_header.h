// A check of an OpenEXR file's header before OpenEXR reads it (issue #25; found by
// tests/fuzz/fuzz_environment_image): OpenEXR 3.1 allocates what an attribute's size field
// claims before reading its value, so a 100-byte file whose string attribute claims 2 GiB made
// readImageHeader allocate and clear 2 GiB. This walks the header(s) itself, reading names and
// size fields only, and refuses any attribute that claims more bytes than the file holds.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace partita {

/// "" when `bytes` are not an OpenEXR file (other formats are not its business) or every
/// attribute of its header(s) fits in them; else why the file is refused, one line.
std::string exrHeaderProblem(std::span<const uint8_t> bytes);

/// The same for a file, reading only its header. "" when it cannot be opened.
std::string exrHeaderProblem(const std::filesystem::path& file);

}  // namespace partita
