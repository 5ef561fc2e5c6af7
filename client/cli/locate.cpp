#include "cli/locate.h"

#include <unistd.h>

#include <cstdlib>
#include <string>
#include <system_error>

#include "cli/errors.h"
#include "cli/file_util.h"

namespace partita::cli {

namespace fs = std::filesystem;

namespace {

bool isExecutableFile(const fs::path& p) {
    std::error_code ec;
    return fs::is_regular_file(p, ec) && ::access(p.c_str(), X_OK) == 0;
}

bool isDirectory(const fs::path& p) {
    std::error_code ec;
    return fs::is_directory(p, ec);
}

}  // namespace

fs::path findPartitad() {
    if (const char* env = std::getenv("PARTITA_PARTITAD"); env && *env) {
        if (!isExecutableFile(env))
            throw CliError(std::string("PARTITA_PARTITAD='") + env + "' is not an executable file");
        return env;
    }
    const fs::path dir = executableDir();
    if (!dir.empty()) {
        for (const fs::path& p : {dir / ".." / "server" / "partitad", dir / "partitad"})
            if (isExecutableFile(p)) return p.lexically_normal();
    }
    if (const char* path = std::getenv("PATH")) {
        std::string s = path;
        size_t start = 0;
        while (start <= s.size()) {
            size_t end = s.find(':', start);
            if (end == std::string::npos) end = s.size();
            if (end > start) {
                fs::path p = fs::path(s.substr(start, end - start)) / "partitad";
                if (isExecutableFile(p)) return p;
            }
            start = end + 1;
        }
    }
    throw CliError(
        "cannot find partitad for a private daemon: pass --server HOST:PORT, set "
        "PARTITA_PARTITAD, or put partitad on PATH");
}

fs::path findSceneRoot() {
    if (const char* env = std::getenv("PARTITA_SCENE_ROOT"); env && *env) {
        if (!isDirectory(env))
            throw CliError(std::string("PARTITA_SCENE_ROOT='") + env + "' is not a folder");
        return env;
    }
    const fs::path dir = executableDir();
    if (!dir.empty()) {
        for (const fs::path& p :
             {dir / ".." / ".." / "scenes", dir / ".." / "share" / "partita" / "scenes"})
            if (isDirectory(p)) return fs::weakly_canonical(p);
    }
#ifdef PARTITA_SOURCE_SCENES_DIR
    if (isDirectory(PARTITA_SOURCE_SCENES_DIR)) return PARTITA_SOURCE_SCENES_DIR;
#endif
    return {};
}

}  // namespace partita::cli
