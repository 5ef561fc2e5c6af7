// partitad's start-up and shutdown (partitad_main.h); see server/README.md.
//
// SIGTERM/SIGINT: stop taking jobs, cancel the running ones (they are re-queued in the store and
// run again after a restart), end the streams, flush the store, exit 0.
#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>
#include <grpcpp/resource_quota.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <climits>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "algorithm.h"
#include "auth.h"
#include "dashboard_server.h"
#include "executor.h"
#include "job_manager.h"
#include "job_memory.h"
#include "job_store.h"
#include "partita_service.h"
#include "partitad_main.h"
#include "protobuf_log.h"
#include "scene_source.h"
#include "server_options.h"
#include "slurm_shards.h"

namespace partita::server {

namespace {

std::string readText(const std::filesystem::path& path, const char* what) {
    std::ifstream in(path, std::ios::binary);
    if (!in)
        throw std::runtime_error(std::string("cannot read ") + what + " '" + path.string() + "'");
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::shared_ptr<grpc::ServerCredentials> credentials(const ServerOptions& o) {
    if (o.tlsCert.empty()) return grpc::InsecureServerCredentials();
    grpc::SslServerCredentialsOptions ssl;
    ssl.pem_key_cert_pairs.push_back(
        {readText(o.tlsKey, "TLS key"), readText(o.tlsCert, "TLS certificate")});
    return grpc::SslServerCredentials(ssl);
}

std::string limitText(int64_t bytes) { return bytes > 0 ? humanBytes(double(bytes)) : "none"; }

int run(const ServerOptions& options, const sigset_t& signals) {
    TokenAuth auth =
        options.tokenFile.empty() ? TokenAuth() : TokenAuth::fromFile(options.tokenFile);
    auto creds = credentials(options);
    registerBuiltinAlgorithms();

    JobStore store(options.store);
    SceneSource scenes(options.sceneRoot);
    JobManager manager(store, scenes, options.limits, options.threads, options.maxJobs,
                       options.cluster);
    manager.start();
    Executor executor(2);
    UploadStaging uploads(
        options.store, options.limits,
        [&manager](uint64_t bytes) { return manager.reserveUploadBytes(bytes); },
        [&manager](uint64_t bytes) { manager.releaseUploadBytes(bytes); });
    PartitaService service(manager, scenes, options.limits, auth, executor, uploads);

    grpc::EnableDefaultHealthCheckService(true);
    grpc::ServerBuilder builder;
    int port = 0;
    builder.AddListeningPort(options.listen, creds, &port);
    builder.RegisterService(&service);
    // gRPC holds a message being received whole (~3x its size): the limit bounds what one
    // request costs before any handler can refuse it. Scenes beyond it stream (UploadScene).
    builder.SetMaxReceiveMessageSize(
        int(std::min<int64_t>(INT_MAX, options.limits.maxMessageBytes)));
    // What a client may have in flight towards partitad is the HTTP/2 window gRPC announces.
    // Its bandwidth-delay probe grows that window without bound on a fast link (measured on
    // loopback: three streamed 96 MiB uploads cost +51-84 MiB, three of 192 MiB +203 MiB);
    // a fixed 1 MiB stream window keeps them at +13-15 MiB whatever their size (1 MiB per
    // round trip: 20 MB/s a stream at 50 ms).
    // gRPC assembles a request whole before it checks its size against the limit above, so
    // the limit alone does not bound what a client sending more costs (three 192 MiB requests
    // at once: +368 MiB). A resource quota on the transport's read buffers does: past it, gRPC
    // resets streams (RESOURCE_EXHAUSTED) and the memory is given back.
    grpc::ResourceQuota receiveQuota("partitad-receive");
    receiveQuota.Resize(size_t(options.limits.maxReceiveBytes));
    builder.SetResourceQuota(receiveQuota);
    builder.AddChannelArgument(GRPC_ARG_HTTP2_BDP_PROBE, 0);
    builder.AddChannelArgument(GRPC_ARG_HTTP2_STREAM_LOOKAHEAD_BYTES, 1 << 20);
    std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
    if (!server || port == 0) throw std::runtime_error("cannot listen on '" + options.listen + "'");
    JobApi api(manager, scenes, options.limits, &uploads);
    std::unique_ptr<dashboard::DashboardServer> dashboard;
    if (!options.http.empty()) {
        dashboard = std::make_unique<dashboard::DashboardServer>(
            api, auth, dashboard::DashboardOptions{options.http, options.tlsCert, options.tlsKey});
        int httpPort = dashboard->start();
        if (!options.httpPortFile.empty())
            JobStore::writeFileAtomic(options.httpPortFile, std::to_string(httpPort) + "\n");
        spdlog::info("dashboard on {}://{} (port {})", options.tlsCert.empty() ? "http" : "https",
                     options.http, httpPort);
    }
    // Written last: a client that sees it finds the dashboard listening too.
    if (!options.portFile.empty())
        JobStore::writeFileAtomic(options.portFile, std::to_string(port) + "\n");

    spdlog::info(
        "partitad {} listening on {} (port {}){}{}; store '{}', scene root '{}', {} threads, {} "
        "jobs at once, job memory limit {}, store limit {}",
        PARTITA_VERSION, options.listen, port, options.tlsCert.empty() ? "" : ", TLS",
        auth.enabled() ? ", token required" : "", options.store.string(),
        scenes.root().empty() ? "(none)" : scenes.root().string(), manager.threads(),
        manager.maxJobs(), limitText(options.limits.maxJobMemoryBytes),
        limitText(options.limits.maxStoreBytes));

    int sig = 0;
    while (sigwait(&signals, &sig) != 0) {
    }
    spdlog::info("{}: shutting down", strsignal(sig));
    if (auto* health = server->GetHealthCheckService()) health->SetServingStatus(false);
    manager.shutdown();  // ends every watch, the dashboard's event streams included
    if (dashboard) dashboard->stop();
    // In-flight calls get a moment to finish; then the rest are cancelled. (gRPC also waits for
    // idle client connections to close until the deadline, so it is kept short.)
    server->Shutdown(std::chrono::system_clock::now() + std::chrono::milliseconds(500));
    server.reset();
    std::error_code ec;
    if (!options.portFile.empty()) std::filesystem::remove(options.portFile, ec);
    if (!options.httpPortFile.empty()) std::filesystem::remove(options.httpPortFile, ec);
    spdlog::info("stopped");
    return 0;
}

}  // namespace

int partitadMain(int argc, char** argv) {
    // Every thread inherits this mask, so SIGINT/SIGTERM are only ever taken by sigwait in run().
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);
    std::signal(SIGPIPE, SIG_IGN);

    ServerOptions options;
    if (int rc = parseServerOptions(argc, argv, options); rc >= 0) return rc;
    if (std::string err = finalizeServerOptions(options); !err.empty()) {
        std::fprintf(stderr, "partitad: error: %s\n", err.c_str());
        return 2;
    }
    if (std::string err = checkSlurmExecutor(options.cluster); !err.empty()) {
        std::fprintf(stderr, "partitad: error: %s\n", err.c_str());
        return 2;
    }
    auto logger = spdlog::stderr_color_mt("partitad");
    spdlog::set_default_logger(logger);
    spdlog::set_pattern("%Y-%m-%d %H:%M:%S.%e %^%l%$ %v");
    spdlog::set_level(spdlog::level::from_str(options.logLevel));
    spdlog::flush_on(spdlog::level::info);
    routeProtobufLogToSpdlog();
    try {
        return run(options, signals);
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        std::fprintf(stderr, "partitad: error: %s\n", e.what());
        return 1;
    }
}

}  // namespace partita::server
