#include "cli/file_util.h"

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "cli/errors.h"
#include "file_io.h"

namespace partita::cli {

namespace fs = std::filesystem;

std::string readFile(const fs::path& path) {
    std::vector<uint8_t> bytes = readFileBytes(path);
    return {bytes.begin(), bytes.end()};
}

void writeFileAtomically(const fs::path& path, std::string_view data) {
    try {
        writeFileAtomic(path, {reinterpret_cast<const uint8_t*>(data.data()), data.size()});
    } catch (const std::runtime_error& e) {
        throw CliError(e.what());
    }
}

fs::path withExtension(fs::path path, const std::string& ext) {
    path.replace_extension(ext);
    return path;
}

fs::path executableDir() {
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return {};
    return exe.parent_path();
}

std::string safeFileName(const std::string& name) {
    std::string out = name;
    for (char& c : out) {
        bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                  c == '.' || c == '_' || c == '=' || c == '-';
        if (!ok) c = '_';
    }
    if (out.empty() || out == "." || out == "..") out = "_" + out;
    return out;
}

}  // namespace partita::cli
