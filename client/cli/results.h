// Downloading a finished job's results: the multi-layer EXR, the PNG preview and the JSON
// metadata, written beside each other (out.exr, out.png, out.json).
#pragma once

#include <filesystem>
#include <string>

#include "cli/connection.h"

namespace partita::cli {

/// The bytes of one result file, assembled from the chunk stream.
std::string fetchResult(Connection& connection, const std::string& jobId,
                        partita::v1::ResultKind kind);

struct ResultFiles {
    std::filesystem::path exr, png, json;
};

/// Fetches all three and writes them (atomically) to exrPath and beside it.
ResultFiles downloadResults(Connection& connection, const std::string& jobId,
                            const std::filesystem::path& exrPath);

/// Throws CliError unless the folder `path` would be written into exists.
void requireOutputFolder(const std::filesystem::path& path);

}  // namespace partita::cli
