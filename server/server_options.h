// partitad's command line (DESIGN.md "Command lines"; keep these flags stable):
//   partitad --listen 127.0.0.1:50051 --store DIR --scene-root DIR [--threads N] [--max-jobs N]
//            [--tls-cert F --tls-key F --token-file F] [--insecure] [--port-file F] [limits...]
//            [--http ADDR [--http-port-file F]]
//            [--executor local|slurm [--slurm-shards N] [--slurm-cpus-per-task N]
//             [--slurm-partition P] [--slurm-worker PATH] [--slurm-poll-seconds S]]
#pragma once

#include <filesystem>
#include <string>

#include "cluster_options.h"
#include "service_limits.h"

namespace partita::server {

struct ServerOptions {
    std::string listen = "127.0.0.1:50051";
    std::filesystem::path store = "partita-store";
    std::filesystem::path sceneRoot;  // empty: ./scenes when it exists, else no named scenes
    int threads = 0;                  // render threads shared by all jobs; 0 = one per core
    int maxJobs = 2;                  // jobs rendering at the same time
    std::filesystem::path tlsCert, tlsKey, tokenFile;
    bool insecure = false;               // allow a non-loopback address without TLS + token
    std::filesystem::path portFile;      // where to write the bound port (use with port 0)
    std::string http;                    // the dashboard's host:port; empty: no dashboard
    std::filesystem::path httpPortFile;  // where to write the dashboard's bound port
    std::string logLevel = "info";
    ServiceLimits limits;
    ClusterOptions cluster;  // --executor and the --slurm-* flags
};

/// Parses argv into `out`. Returns -1 to go on, or the exit code to stop with (0 after --help or
/// --version; 2 after a usage error, already reported on stderr).
int parseServerOptions(int argc, char** argv, ServerOptions& out);

/// Checks the flags together (the TLS pair, the non-loopback rule, value ranges) and fills in
/// defaults that depend on the file system. Returns "" or one line saying what is wrong.
std::string finalizeServerOptions(ServerOptions& options);

/// True for 127.0.0.0/8, ::1, "localhost" and unix: sockets. `listen` is "host:port",
/// "[v6]:port" or "unix:path".
bool isLoopbackAddress(const std::string& listen);

}  // namespace partita::server
