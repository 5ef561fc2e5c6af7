#include "cli/private_daemon.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <thread>
#include <vector>

#include "cli/connection.h"
#include "cli/errors.h"
#include "cli/file_util.h"
#include "cli/health.h"
#include "cli/locate.h"
#include "cli/signals.h"

namespace partita::cli {

namespace fs = std::filesystem;

namespace {

fs::path makeTempDir() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern =
        (tmp && *tmp ? std::string(tmp) : std::string("/tmp")) + "/partita-XXXXXX";
    std::vector<char> buf(pattern.begin(), pattern.end());
    buf.push_back('\0');
    if (!::mkdtemp(buf.data()))
        throw CliError("cannot create a temporary folder for the private daemon under '" +
                       fs::path(pattern).parent_path().string() + "'");
    return fs::path(buf.data());
}

/// The port in the port file, 0 while it is not (completely) written yet.
int readPort(const fs::path& file) {
    std::ifstream in(file);
    long port = 0;
    if (!(in >> port) || port <= 0 || port > 65535) return 0;
    return int(port);
}

}  // namespace

PrivateDaemon::PrivateDaemon(const Options& options) {
    try {
        start(options);
    } catch (...) {
        stop();
        throw;
    }
}

PrivateDaemon::~PrivateDaemon() { stop(); }

void PrivateDaemon::start(const Options& options) {
    const fs::path partitad = findPartitad();
    fs::path sceneRoot = findSceneRoot();
    dir_ = makeTempDir();
    const fs::path store = dir_ / "store", portFile = dir_ / "port", log = dir_ / "partitad.log";
    fs::create_directory(store);
    if (sceneRoot.empty()) {
        sceneRoot = dir_ / "scenes";
        fs::create_directory(sceneRoot);
    }

    std::vector<std::string> args = {partitad.string(), "--listen",        "127.0.0.1:0",
                                     "--port-file",     portFile.string(), "--store",
                                     store.string(),    "--scene-root",    sceneRoot.string()};
    if (options.threads > 0) {
        args.push_back("--threads");
        args.push_back(std::to_string(options.threads));
    }
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const std::string logPath = log.string();
    const pid_t parent = ::getpid();

    pid_t pid = ::fork();
    if (pid < 0) throw CliError("cannot start the private partitad: fork failed");
    if (pid == 0) {
        // Child: only async-signal-safe calls until exec.
        ::setpgid(0, 0);
        ::prctl(PR_SET_PDEATHSIG, SIGTERM);
        if (::getppid() != parent) ::_exit(127);
        int fd = ::open(logPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
        if (fd >= 0) {
            ::dup2(fd, STDOUT_FILENO);
            ::dup2(fd, STDERR_FILENO);
        }
        int nul = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
        if (nul >= 0) ::dup2(nul, STDIN_FILENO);
        ::execv(argv[0], argv.data());
        ::_exit(127);
    }
    pid_ = pid;

    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::milliseconds(int64_t(options.startTimeoutSeconds * 1000));
    std::shared_ptr<grpc::Channel> channel;
    while (true) {
        int status = 0;
        if (::waitpid(pid_, &status, WNOHANG) == pid_) {
            pid_ = -1;
            std::string why = lastLogLine();
            std::string how = WIFEXITED(status)
                                  ? "exit status " + std::to_string(WEXITSTATUS(status))
                                  : "signal " + std::to_string(WTERMSIG(status));
            if (WIFEXITED(status) && WEXITSTATUS(status) == 127 && why.empty())
                why = "cannot execute '" + partitad.string() + "'";
            throw CliError("the private partitad did not start (" + how + ")" +
                           (why.empty() ? std::string() : ": " + why));
        }
        if (interrupted()) throw CliError("interrupted", "", 130);
        if (!channel) {
            if (int port = readPort(portFile); port > 0) {
                address_ = "127.0.0.1:" + std::to_string(port);
                channel = makeChannel(address_, ServerOptions{});
            }
        }
        if (channel) {
            HealthResult health = checkHealth(channel, "", 1.0);
            // A server without the health service still answered: it is up.
            if (health.serving || health.status.error_code() == grpc::StatusCode::UNIMPLEMENTED)
                return;
        }
        if (std::chrono::steady_clock::now() > deadline)
            throw CliError("the private partitad did not become ready within " +
                           std::to_string(int(options.startTimeoutSeconds)) + " s" +
                           (lastLogLine().empty() ? std::string() : ": " + lastLogLine()));
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
}

std::string PrivateDaemon::lastLogLine() const {
    std::ifstream in(dir_ / "partitad.log");
    std::string line, last;
    while (std::getline(in, line))
        if (!oneLine(line).empty()) last = oneLine(line);
    return last;
}

void PrivateDaemon::stop() {
    if (pid_ > 0) {
        ::kill(pid_, SIGTERM);
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        int status = 0;
        while (::waitpid(pid_, &status, WNOHANG) == 0) {
            if (std::chrono::steady_clock::now() > deadline) {
                ::kill(pid_, SIGKILL);
                ::waitpid(pid_, &status, 0);
                break;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        pid_ = -1;
    }
    if (!dir_.empty()) {
        std::error_code ec;
        fs::remove_all(dir_, ec);
        dir_.clear();
    }
}

}  // namespace partita::cli
