// How much disk the job store uses, for the store size limit (--max-store-mb): a new upload that
// would take the store over it is refused with RESOURCE_EXHAUSTED, so that queued uploads
// (up to --max-queued of --max-upload-mb each) cannot fill the disk.
#pragma once

#include <cstdint>
#include <filesystem>

namespace partita::server {

/// The bytes of every regular file under `dir` (symlinks not followed; unreadable entries
/// skipped; a file with several hard links, a staged upload and its jobs', counted once). Walks the
/// folder: cheap next to receiving an upload.
uint64_t folderBytes(const std::filesystem::path& dir);

/// Half the capacity of the file system holding `path` (or its nearest existing parent), at most
/// its free space plus what `path` already holds; 0 when
/// unknown. The default store size limit.
uint64_t defaultStoreLimit(const std::filesystem::path& path);

}  // namespace partita::server
