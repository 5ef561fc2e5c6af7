#include "cli/file_util.h"

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "cli/errors.h"

namespace partita::cli {

namespace fs = std::filesystem;

std::string readFile(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open '" + path.string() + "'");
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) throw std::runtime_error("cannot read '" + path.string() + "'");
    return ss.str();
}

void writeFileAtomically(const fs::path& path, std::string_view data) {
    fs::path tmp = path;
    tmp += ".part";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw CliError("cannot write '" + path.string() + "'");
        out.write(data.data(), std::streamsize(data.size()));
        out.flush();
        if (!out) {
            std::error_code ec;
            fs::remove(tmp, ec);
            throw CliError("cannot write '" + path.string() + "' (disk full?)");
        }
    }
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw CliError("cannot write '" + path.string() + "': " + ec.message());
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
