// The server a command talks to: the one named by --server, or a private daemon started for
// this command (private_daemon.h) and stopped when the session ends.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/connection.h"
#include "cli/private_daemon.h"

namespace partita::cli {

/// The options every command shares.
struct GlobalOptions {
    ServerOptions server;
    bool quiet = false;  // no progress bar, no informational lines
    /// The --algorithm of the command line, read before parsing: --help lists its parameters.
    std::string helpAlgorithm;
};

class Session {
  public:
    /// `threads` is passed to a private daemon (ignored with --server).
    Session(const GlobalOptions& global, int threads = 0);
    ~Session();

    Connection& connection() { return *connection_; }
    bool isPrivate() const { return daemon_ != nullptr; }

    /// Checks an algorithm name against the server's list (GetServerInfo), so that a typo fails
    /// before anything is uploaded. Throws CliError(..., "INVALID_ARGUMENT").
    void checkAlgorithm(const std::string& algorithm);

    /// Checks a spec's size, budget and depth against the server's own limits (GetServerInfo),
    /// before anything is uploaded. Throws CliError(..., "RESOURCE_EXHAUSTED") naming the limit.
    void checkLimits(const partita::v1::JobSpec& spec);

    /// The parameters (CLI spelling) that change what `algorithm` renders on this server; empty
    /// when the server does not say.
    std::vector<std::string> algorithmParameters(const std::string& algorithm);

    /// GetServerInfo, asked once (empty for a server without it).
    const partita::v1::ServerInfo& serverInfo();

  private:
    std::optional<partita::v1::ServerInfo> info_;
    std::unique_ptr<PrivateDaemon> daemon_;
    std::unique_ptr<Connection> connection_;
};

/// How long a command waits for a --server that does not answer yet.
constexpr double kServerWaitSeconds = 5;

/// Throws CliError when no --server is given: `command` works on jobs of a lasting server.
void requireServer(const GlobalOptions& global, const std::string& command);

}  // namespace partita::cli
