// Running the real binaries from tests: a command with captured stdout/stderr and a timeout, and
// a partitad started on 127.0.0.1 port 0 with a temporary store.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <condition_variable>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <thread>
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

/// A pseudo-terminal of `columns` x `rows` (set with TIOCSWINSZ, as a terminal emulator does).
/// What is written to its slave side comes out of its master, which a thread reads from the
/// start (so that a writer never blocks on a full buffer) until every copy of the slave is
/// closed. The slave keeps the terminal's usual settings (a "\n" comes out as "\r\n").
class PseudoTerminal {
  public:
    PseudoTerminal(int columns, int rows);
    ~PseudoTerminal();
    PseudoTerminal(const PseudoTerminal&) = delete;
    PseudoTerminal& operator=(const PseudoTerminal&) = delete;
    /// The slave's descriptor (close-on-exec: dup2 it into a child, or dup it).
    int slave() const { return slave_; }
    /// Closes the slave here and returns all that came out of the master once every other copy
    /// of the slave is closed too; what came so far after `timeoutSeconds`.
    std::string finish(double timeoutSeconds = 60);

  private:
    void readMaster();
    int master_ = -1, slave_ = -1;
    std::mutex mutex_;
    std::condition_variable endedChanged_;
    bool ended_ = false;  // the reader is done: every copy of the slave is closed
    std::atomic<bool> stop_{false};
    std::string output_;
    std::thread reader_;
};

/// Runs `args` like runProgram, but with its stderr on a pseudo-terminal of `columns` x `rows`
/// (stdin /dev/null, stdout a file): RunResult::err is what the terminal received, escape
/// sequences included.
RunResult runInTerminal(const std::vector<std::string>& args, int columns, int rows,
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

/// partitad --listen 127.0.0.1:0 --port-file ... --store <tmp> --scene-root <repo>/scenes;
/// `binary`: another build of it (a daemon with a test's own algorithm).
class Daemon {
  public:
    explicit Daemon(const std::vector<std::string>& extraArgs = {},
                    const std::string& binary = PARTITAD_PATH);
    ~Daemon();
    const std::string& address() const { return address_; }
    std::filesystem::path store() const { return dir_.path() / "store"; }
    std::string log() const;

  private:
    TempDir dir_;
    pid_t pid_ = -1;
    std::string address_;
};

}  // namespace partita::test
