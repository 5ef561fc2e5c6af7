#include "cli/session.h"

#include "cli/job_spec.h"

#include <cfloat>
#include <climits>
#include <cstdint>

#include "cli/table.h"
#include "frontend/progress_bar.h"
#include "params/job_parameters.h"

namespace partita::cli {

Session::Session(const GlobalOptions& global, int threads) {
    if (global.server.server.empty()) {
        daemon_ = std::make_unique<PrivateDaemon>(PrivateDaemon::Options{threads, 30});
        connection_ = std::make_unique<Connection>(daemon_->address(), ServerOptions{});
    } else {
        connection_ = std::make_unique<Connection>(global.server.server, global.server);
        // Only on a terminal: in logs and scripts, a failure stays one line.
        connection_->waitForServer(kServerWaitSeconds,
                                   !global.quiet && ProgressBar::stderrIsTerminal());
    }
}

Session::~Session() {
    connection_.reset();
    if (daemon_) daemon_->stop();
}

const partita::v1::ServerInfo& Session::serverInfo() {
    if (info_) return *info_;
    grpc::ClientContext context;
    connection_->prepare(context, 30);
    partita::v1::ServerInfo info;
    grpc::Status status =
        connection_->stub().GetServerInfo(&context, partita::v1::ServerInfoRequest{}, &info);
    if (status.error_code() == grpc::StatusCode::UNIMPLEMENTED)
        info.Clear();
    else if (!status.ok())
        connection_->fail(status, "");
    info_ = std::move(info);
    return *info_;
}

std::vector<std::string> Session::algorithmParameters(const std::string& algorithm) {
    for (const auto& a : serverInfo().algorithms())
        if (a.name() == algorithm) return {a.parameters().begin(), a.parameters().end()};
    return {};
}

void Session::checkLimits(const partita::v1::JobSpec& spec) {
    if (!serverInfo().has_limits()) return;
    // The core's own rules with this server's limits (GetServerInfo), not a copy of them: what
    // fails here is over a limit, the rest having passed validateJobSpec already.
    const partita::v1::Limits& l = serverInfo().limits();
    RenderLimits limits;
    auto or_ = [](auto limit, auto unlimited) {
        return limit > 0 ? decltype(unlimited)(limit) : unlimited;
    };
    limits.maxWidth = or_(l.max_width(), INT_MAX);
    limits.maxHeight = or_(l.max_height(), INT_MAX);
    limits.maxDepth = or_(l.max_depth(), INT_MAX);
    limits.maxSamplesPerPixel = or_(l.max_samples_per_pixel(), DBL_MAX);
    limits.maxSeconds = or_(l.max_seconds(), DBL_MAX);
    limits.maxBootstrapSamples = or_(l.max_bootstrap_samples(), UINT64_MAX);
    std::string error;
    const RenderSettings s = settingsOfSpec(spec, error);
    if (!error.empty()) return;  // the server's message says what is wrong
    registerBuiltinAlgorithms();
    const auto* entry = AlgorithmRegistry::instance().find(spec.algorithm());
    std::string why = entry ? validateJob(*entry, s, limits) : validateSettings(s, limits);
    if (!why.empty()) throw CliError(why, "RESOURCE_EXHAUSTED");
}

void Session::checkAlgorithm(const std::string& algorithm) {
    const partita::v1::ServerInfo& info = serverInfo();
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
