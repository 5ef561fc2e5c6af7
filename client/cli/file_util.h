// Small file helpers of the CLI.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace partita::cli {

/// The whole file; throws std::runtime_error naming it.
std::string readFile(const std::filesystem::path& path);

/// core's writeFileAtomic (file_io.h): readers never see a half written file. Throws CliError
/// naming the file.
void writeFileAtomically(const std::filesystem::path& path, std::string_view data);

/// `path` with its extension replaced ("out.exr" -> "out.png").
std::filesystem::path withExtension(std::filesystem::path path, const std::string& ext);

/// The folder of the running executable (/proc/self/exe), empty if unknown.
std::filesystem::path executableDir();

/// A name safe as a file name: everything but [A-Za-z0-9._=-] becomes '_'.
std::string safeFileName(const std::string& name);

}  // namespace partita::cli
