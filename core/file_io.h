// Whole files in and out: a file read in one go, and an atomic write (a temporary file with a
// name of its own, fsync, rename, fsync of the folder), so that a reader, or a second writer
// of the same file (a retried shard, partitad's store), never sees half a file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <vector>

namespace partita {

/// The whole file, or std::runtime_error("cannot read '<path>'").
std::vector<uint8_t> readFileBytes(const std::filesystem::path& path);

/// Checks, before any work, that `file` could be written: its folder exists and it is not a
/// folder itself. std::runtime_error("cannot write '<file>': ...") otherwise. Every front end
/// calls it before it renders, so that a mistyped output path costs nothing.
void requireOutputFolder(const std::filesystem::path& file);

/// Writes `bytes` to `path` atomically (above); std::runtime_error("cannot write ...").
void writeFileAtomic(const std::filesystem::path& path, std::span<const uint8_t> bytes);

/// The same, for contents written straight to the file by `write` (given the open descriptor;
/// false on failure, errno set): no copy of them in memory first (a serialised upload).
void writeFileAtomic(const std::filesystem::path& path, const std::function<bool(int fd)>& write);

}  // namespace partita
