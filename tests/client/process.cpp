#include "process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/ioctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace partita::test {

namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

std::vector<std::string> RunResult::errLines() const {
    std::vector<std::string> lines;
    std::istringstream in(err);
    std::string line;
    while (std::getline(in, line))
        if (line.find_first_not_of(" \t\r") != std::string::npos) lines.push_back(line);
    return lines;
}

std::string RunResult::describe() const {
    return "exit " + std::to_string(exitCode) + "\n--- stdout ---\n" + out + "--- stderr ---\n" +
           err;
}

TempDir::TempDir() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/partita-client-test-XXXXXX";
    if (!::mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
    path_ = pattern;
}

TempDir::~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
}

namespace {

using Clock = std::chrono::steady_clock;

Clock::time_point after(Clock::time_point start, double seconds) {
    return start +
           std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

/// Starts `args` with the file actions (destroyed here) and this process's environment plus
/// `env`.
pid_t spawnProgram(const std::vector<std::string>& args,
                   const std::map<std::string, std::string>& env,
                   posix_spawn_file_actions_t& actions) {
    std::vector<std::string> envStrings;
    for (char** e = environ; *e; ++e) {
        std::string s = *e;
        std::string key = s.substr(0, s.find('='));
        if (!env.count(key)) envStrings.push_back(s);
    }
    for (const auto& [k, v] : env) envStrings.push_back(k + "=" + v);
    std::vector<char*> argv, envp;
    std::vector<std::string> argsCopy = args;
    for (auto& a : argsCopy) argv.push_back(a.data());
    argv.push_back(nullptr);
    for (auto& e : envStrings) envp.push_back(e.data());
    envp.push_back(nullptr);
    pid_t pid = -1;
    int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) throw std::runtime_error("cannot run " + args[0]);
    return pid;
}

/// Waits for `pid` until `deadline`, then kills it; its exit code, 128 + signal when killed.
int waitUntil(pid_t pid, Clock::time_point deadline) {
    int status = 0;
    while (true) {
        pid_t w = ::waitpid(pid, &status, WNOHANG);
        if (w == pid) break;
        if (Clock::now() > deadline) {
            ::kill(pid, SIGKILL);
            ::waitpid(pid, &status, 0);
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace

RunResult runProgram(const std::vector<std::string>& args,
                     const std::map<std::string, std::string>& env, double timeoutSeconds) {
    TempDir io;
    const fs::path outPath = io / "stdout", errPath = io / "stderr";
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, outPath.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, errPath.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    RunResult result;
    const auto start = Clock::now();
    const pid_t pid = spawnProgram(args, env, actions);
    result.exitCode = waitUntil(pid, after(start, timeoutSeconds));
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    result.out = slurp(outPath);
    result.err = slurp(errPath);
    return result;
}

PseudoTerminal::PseudoTerminal(int columns, int rows) {
    master_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (master_ < 0 || ::grantpt(master_) != 0 || ::unlockpt(master_) != 0) {
        if (master_ >= 0) ::close(master_);
        throw std::runtime_error("cannot open a pseudo-terminal");
    }
    char name[128];
    if (::ptsname_r(master_, name, sizeof name) != 0 ||
        (slave_ = ::open(name, O_RDWR | O_NOCTTY | O_CLOEXEC)) < 0) {
        ::close(master_);
        throw std::runtime_error("cannot open the pseudo-terminal's slave");
    }
    winsize size{};
    size.ws_col = static_cast<unsigned short>(columns);
    size.ws_row = static_cast<unsigned short>(rows);
    if (::ioctl(master_, TIOCSWINSZ, &size) != 0) {
        ::close(slave_);
        ::close(master_);
        throw std::runtime_error("cannot set the pseudo-terminal's size");
    }
    reader_ = std::thread([this] { readMaster(); });
}

PseudoTerminal::~PseudoTerminal() {
    stop_ = true;
    if (reader_.joinable()) reader_.join();
    if (slave_ >= 0) ::close(slave_);
    ::close(master_);
}

void PseudoTerminal::readMaster() {
    char buffer[4096];
    while (!stop_) {
        pollfd p{master_, POLLIN, 0};
        int ready = ::poll(&p, 1, 100);  // looks at stop_ at least every 100 ms
        if (ready < 0 && errno != EINTR) break;
        if (ready <= 0) continue;
        ssize_t n = ::read(master_, buffer, sizeof buffer);
        if (n > 0) {
            std::lock_guard lock(mutex_);
            output_.append(buffer, size_t(n));
            continue;
        }
        if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
        break;  // EIO (Linux) or 0: every copy of the slave is closed, and all it sent was read
    }
    std::lock_guard lock(mutex_);
    ended_ = true;
    endedChanged_.notify_all();
}

std::string PseudoTerminal::finish(double timeoutSeconds) {
    if (slave_ >= 0) {
        ::close(slave_);
        slave_ = -1;
    }
    std::unique_lock lock(mutex_);
    endedChanged_.wait_for(lock, std::chrono::duration<double>(timeoutSeconds),
                           [this] { return ended_; });
    return output_;
}

RunResult runInTerminal(const std::vector<std::string>& args, int columns, int rows,
                        const std::map<std::string, std::string>& env, double timeoutSeconds) {
    TempDir io;
    const fs::path outPath = io / "stdout";
    PseudoTerminal terminal(columns, rows);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, outPath.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, terminal.slave(), STDERR_FILENO);
    RunResult result;
    const auto start = Clock::now();
    const pid_t pid = spawnProgram(args, env, actions);
    // The terminal's output ends when the program (and whatever it started on its stderr) has
    // closed it; a program that hangs is killed at the deadline, and what it wrote until then is
    // what the terminal received.
    terminal.finish(timeoutSeconds);
    result.exitCode =
        waitUntil(pid, std::max(after(start, timeoutSeconds), after(Clock::now(), 1)));
    result.err = terminal.finish(5);
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    result.out = slurp(outPath);
    return result;
}

Daemon::Daemon(const std::vector<std::string>& extraArgs, const std::string& binary) {
    const fs::path portFile = dir_ / "port", log = dir_ / "partitad.log";
    fs::create_directory(dir_ / "store");
    std::vector<std::string> args = {binary,
                                     "--listen",
                                     "127.0.0.1:0",
                                     "--port-file",
                                     portFile.string(),
                                     "--store",
                                     (dir_ / "store").string(),
                                     "--scene-root",
                                     PARTITA_SCENES_DIR,
                                     "--threads",
                                     "2"};
    args.insert(args.end(), extraArgs.begin(), extraArgs.end());
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    int rc = posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) throw std::runtime_error("cannot start partitad");
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (std::chrono::steady_clock::now() < deadline) {
        int status = 0;
        if (::waitpid(pid_, &status, WNOHANG) == pid_) {
            pid_ = -1;
            throw std::runtime_error("partitad exited: " + log.string() + ": " + slurp(log));
        }
        std::ifstream in(portFile);
        int port = 0;
        if (in >> port && port > 0) {
            address_ = "127.0.0.1:" + std::to_string(port);
            return;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    throw std::runtime_error("partitad did not write its port file: " + slurp(log));
}

Daemon::~Daemon() {
    if (pid_ > 0) {
        ::kill(pid_, SIGTERM);
        int status = 0;
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (::waitpid(pid_, &status, WNOHANG) == 0) {
            if (std::chrono::steady_clock::now() > deadline) {
                ::kill(pid_, SIGKILL);
                ::waitpid(pid_, &status, 0);
                break;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
    }
}

std::string Daemon::log() const { return slurp(dir_ / "partitad.log"); }

}  // namespace partita::test
