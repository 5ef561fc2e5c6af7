#include "file_io.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>

namespace partita {

namespace fs = std::filesystem;

namespace {

void fsyncPath(const fs::path& p, int flags) {
    int fd = ::open(p.c_str(), flags | O_CLOEXEC);
    if (fd < 0) return;
    ::fsync(fd);
    ::close(fd);
}

}  // namespace

std::vector<uint8_t> readFileBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw std::runtime_error("cannot read '" + path.string() + "'");
    const std::streamoff size = in.tellg();
    if (size < 0) throw std::runtime_error("cannot read '" + path.string() + "'");
    std::vector<uint8_t> bytes(static_cast<size_t>(size));
    in.seekg(0);
    if (!in.read(reinterpret_cast<char*>(bytes.data()), size))
        throw std::runtime_error("cannot read '" + path.string() + "'");
    return bytes;
}

void writeFileAtomic(const fs::path& path, std::span<const uint8_t> bytes) {
    writeFileAtomic(path, [&](int fd) {
        const uint8_t* p = bytes.data();
        size_t left = bytes.size();
        while (left > 0) {
            ssize_t n = ::write(fd, p, left);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) return false;
            p += n;
            left -= size_t(n);
        }
        return true;
    });
}

void writeFileAtomic(const fs::path& path, const std::function<bool(int fd)>& write) {
    static std::atomic<uint64_t> counter{0};
    fs::path tmp = path;
    tmp += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
    int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0)
        throw std::runtime_error("cannot write '" + path.string() + "': " + std::strerror(errno));
    errno = 0;
    if (!write(fd)) {
        int err = errno ? errno : EIO;
        ::close(fd);
        ::unlink(tmp.c_str());
        throw std::runtime_error("cannot write '" + path.string() + "': " + std::strerror(err));
    }
    if (::fsync(fd) != 0 || ::close(fd) != 0) {
        int err = errno;
        ::unlink(tmp.c_str());
        throw std::runtime_error("cannot write '" + path.string() + "': " + std::strerror(err));
    }
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        int err = errno;
        ::unlink(tmp.c_str());
        throw std::runtime_error("cannot write '" + path.string() + "': " + std::strerror(err));
    }
    fsyncPath(path.parent_path(), O_RDONLY | O_DIRECTORY);
}

void requireOutputFolder(const std::filesystem::path& file) {
    namespace fs = std::filesystem;
    const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        throw std::runtime_error("cannot write '" + file.string() + "': folder '" + dir.string() +
                                 "' does not exist");
    if (fs::is_directory(file, ec))
        throw std::runtime_error("cannot write '" + file.string() + "': it is a folder");
}

}  // namespace partita
