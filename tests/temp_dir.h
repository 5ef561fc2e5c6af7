// A fresh folder under the system's temporary folder, removed with everything in it: what the
// service tests and the job-system tests (tests/server) give a store.
#pragma once

#include <filesystem>
#include <random>
#include <string>

#include <unistd.h>

namespace partita::test {

class TempDir {
  public:
    TempDir() {
        std::random_device rd;
        for (;;) {
            path_ = std::filesystem::temp_directory_path() /
                    ("partita-test-" + std::to_string(::getpid()) + "-" +
                     std::to_string(rd() & 0xffffff));
            if (std::filesystem::create_directory(path_)) break;
        }
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

  private:
    std::filesystem::path path_;
};

}  // namespace partita::test
