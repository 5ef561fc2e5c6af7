#include "cli/session.h"

#include "cli/job_spec.h"
#include "cli/table.h"
#include "frontend/progress_bar.h"

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
    const partita::v1::Limits& l = serverInfo().limits();
    auto over = [](const std::string& what, double value, double limit, const char* unit) {
        throw CliError(what + " " + formatCount(value) + " exceeds the server's limit of " +
                           formatCount(limit) + unit,
                       "RESOURCE_EXHAUSTED");
    };
    std::string error;
    const RenderSettings s = settingsOfSpec(spec, error);
    if (!error.empty()) return;  // the server's message says what is wrong
    if (l.max_width() > 0 && s.width > l.max_width())
        over("--width", s.width, l.max_width(), " pixels");
    if (l.max_height() > 0 && s.height > l.max_height())
        over("--height", s.height, l.max_height(), " pixels");
    if (l.max_depth() > 0 && s.maxDepth > l.max_depth())
        over("--max-depth", s.maxDepth, l.max_depth(), "");
    const auto& b = spec.budget();
    if (b.kind() == partita::v1::BUDGET_KIND_SECONDS) {
        if (l.max_seconds() > 0 && b.amount() > l.max_seconds())
            over("--seconds", b.amount(), l.max_seconds(), " s");
    } else if (b.kind() != partita::v1::BUDGET_KIND_UNSPECIFIED) {
        const char* flag =
            b.kind() == partita::v1::BUDGET_KIND_SAMPLES_PER_PIXEL ? "--spp" : "--mpp";
        if (l.max_samples_per_pixel() > 0 && b.amount() > l.max_samples_per_pixel())
            over(flag, b.amount(), l.max_samples_per_pixel(), " per pixel");
    }
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
