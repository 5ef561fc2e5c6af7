// Running the real binaries from tests: a command with captured stdout/stderr and a timeout, and
// a partitad started on 127.0.0.1 port 0 with a temporary store.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace partita::test {

struct RunResult {
    int exitCode = -1;  // 128 + signal when killed
    std::string out, err;
    double seconds = 0;
    /// Non-empty lines of stderr.
    std::vector<std::string> errLines() const;
    std::string describe() const;  // for assertion messages
};

/// Runs `args` (args[0] the program) with extra environment variables; kills it after
/// `timeoutSeconds`.
RunResult runProgram(const std::vector<std::string>& args,
                     const std::map<std::string, std::string>& env = {},
                     double timeoutSeconds = 90);

/// A fresh folder under $TMPDIR or /tmp, removed by the destructor.
class TempDir {
  public:
    TempDir();
    ~TempDir();
    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

  private:
    std::filesystem::path path_;
};

/// partitad --listen 127.0.0.1:0 --port-file ... --store <tmp> --scene-root <repo>/scenes.
class Daemon {
  public:
    explicit Daemon(const std::vector<std::string>& extraArgs = {});
    ~Daemon();
    const std::string& address() const { return address_; }
    std::string log() const;

  private:
    TempDir dir_;
    pid_t pid_ = -1;
    std::string address_;
};

}  // namespace partita::test
