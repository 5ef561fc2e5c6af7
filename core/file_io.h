// Whole files in and out: a file read in one go, and an atomic write (a temporary file with a
// name of its own, fsync, rename, fsync of the folder), so that a reader, or a second writer
// of the same file (a retried shard, partitad's store), never sees half a file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace partita {

/// The whole file, or std::runtime_error("cannot read '<path>'").
std::vector<uint8_t> readFileBytes(const std::filesystem::path& path);

/// Writes `bytes` to `path` atomically (above); std::runtime_error("cannot write ...").
void writeFileAtomic(const std::filesystem::path& path, std::span<const uint8_t> bytes);

}  // namespace partita
