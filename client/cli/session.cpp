#include "cli/session.h"

namespace partita::cli {

Session::Session(const GlobalOptions& global, int threads) {
    if (global.server.server.empty()) {
        daemon_ = std::make_unique<PrivateDaemon>(PrivateDaemon::Options{threads, 30});
        connection_ = std::make_unique<Connection>(daemon_->address(), ServerOptions{});
    } else {
        connection_ = std::make_unique<Connection>(global.server.server, global.server);
    }
}

Session::~Session() {
    connection_.reset();
    if (daemon_) daemon_->stop();
}

void Session::checkAlgorithm(const std::string& algorithm) {
    grpc::ClientContext context;
    connection_->prepare(context, 30);
    partita::v1::ServerInfo info;
    grpc::Status status =
        connection_->stub().GetServerInfo(&context, partita::v1::ServerInfoRequest{}, &info);
    if (status.error_code() == grpc::StatusCode::UNIMPLEMENTED) return;
    if (!status.ok()) connection_->fail(status, "");
    if (info.algorithms().empty()) return;
    std::string known;
    for (const auto& a : info.algorithms()) {
        if (a.name() == algorithm) return;
        known += (known.empty() ? "" : ", ") + a.name();
    }
    throw CliError("unknown algorithm '" + algorithm + "' (the server offers: " + known + ")",
                   "INVALID_ARGUMENT");
}

void requireServer(const GlobalOptions& global, const std::string& command) {
    if (global.server.server.empty())
        throw CliError(command +
                       " needs --server HOST:PORT (without it, a private daemon with "
                       "no jobs would be started)");
}

}  // namespace partita::cli
