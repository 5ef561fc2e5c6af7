#include "server_options.h"

#include <arpa/inet.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <cstring>

#include "job_memory.h"
#include "store_usage.h"

namespace partita::server {

namespace fs = std::filesystem;

namespace {

/// The host part of "host:port" or "[v6]:port" ("" when malformed).
std::string hostOf(const std::string& listen) {
    if (!listen.empty() && listen.front() == '[') {
        size_t close = listen.find(']');
        return close == std::string::npos ? "" : listen.substr(1, close - 1);
    }
    size_t colon = listen.rfind(':');
    return colon == std::string::npos ? listen : listen.substr(0, colon);
}

}  // namespace

bool isLoopbackAddress(const std::string& listen) {
    if (listen.rfind("unix:", 0) == 0 || listen.rfind("unix-abstract:", 0) == 0) return true;
    std::string host = hostOf(listen);
    if (host == "localhost") return true;
    in_addr v4{};
    if (inet_pton(AF_INET, host.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
    in6_addr v6{};
    if (inet_pton(AF_INET6, host.c_str(), &v6) == 1) {
        if (std::memcmp(&v6, &in6addr_loopback, sizeof v6) == 0) return true;
        // ::ffff:127.x.y.z
        static const unsigned char mapped[12] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xff, 0xff};
        return std::memcmp(v6.s6_addr, mapped, 12) == 0 && v6.s6_addr[12] == 127;
    }
    return false;
}

int parseServerOptions(int argc, char** argv, ServerOptions& o) {
    CLI::App app{"partitad: the Partita render daemon (gRPC service partita.v1.Partita)"};
    app.set_version_flag("--version", PARTITA_VERSION);
    double uploadMb = double(o.limits.maxUploadBytes) / (1 << 20);
    double rawPreviewMb = double(o.limits.maxRawPreviewBytes) / (1 << 20);
    double messageMb = double(o.limits.maxMessageBytes) / (1 << 20);
    double receiveMb = -1;  // -1: the default, at least twice the message limit (below)
    double uploadTtlMinutes = o.limits.uploadTtlSeconds / 60;
    double jobMemoryMb = -1, totalMemoryMb = -1,
           storeMb = -1;  // -1: the defaults finalizeServerOptions computes
    app.add_option("--listen", o.listen, "address to listen on, host:port (port 0: any free port)")
        ->capture_default_str();
    app.add_option("--store", o.store, "job store folder (SQLite database + one folder per job)")
        ->capture_default_str();
    app.add_option("--scene-root", o.sceneRoot,
                   "folder of named scenes (default: ./scenes if it exists)");
    app.add_option("--threads", o.threads, "render threads shared by all jobs (0: one per core)")
        ->capture_default_str();
    app.add_option("--max-jobs", o.maxJobs, "jobs rendering at the same time")
        ->capture_default_str();
    app.add_option("--tls-cert", o.tlsCert, "PEM certificate chain: serve TLS (with --tls-key)");
    app.add_option("--tls-key", o.tlsKey, "PEM private key of --tls-cert");
    app.add_option("--token-file", o.tokenFile,
                   "file holding the token clients must send as 'authorization: Bearer <token>'");
    app.add_flag("--insecure", o.insecure, "allow a non-loopback address without TLS and token");
    app.add_option("--port-file", o.portFile, "write the bound port to this file once listening");
    app.add_option("--http", o.http,
                   "serve the browser dashboard on host:port (port 0: any free port); off when "
                   "not given. The same TLS, token and loopback rules as --listen");
    app.add_option("--http-port-file", o.httpPortFile,
                   "write the dashboard's bound port to this file once listening");
    app.add_option("--log-level", o.logLevel, "trace, debug, info, warn, error")
        ->capture_default_str();
    app.add_option("--max-width", o.limits.maxWidth, "largest image width")->capture_default_str();
    app.add_option("--max-height", o.limits.maxHeight, "largest image height")
        ->capture_default_str();
    app.add_option("--max-spp", o.limits.maxSamplesPerPixel,
                   "largest samples (or mutations) per pixel")
        ->capture_default_str();
    app.add_option("--max-seconds", o.limits.maxSeconds, "largest time budget, seconds")
        ->capture_default_str();
    app.add_option("--max-upload-mb", uploadMb, "largest uploaded scene (all its files), MiB")
        ->capture_default_str();
    app.add_option("--max-message-mb", messageMb,
                   "largest request message, MiB: a scene sent inside SubmitJob must fit it "
                   "(clients stream larger ones through UploadScene); gRPC holds a message being "
                   "received whole")
        ->capture_default_str();
    app.add_option("--max-receive-mb", receiveMb,
                   "memory gRPC may hold for requests being received, all connections "
                   "together, MiB (at least twice --max-message-mb; default 256, or twice "
                   "--max-message-mb if more): beyond it, streams are reset with "
                   "RESOURCE_EXHAUSTED, also a request larger than --max-message-mb that gRPC "
                   "would otherwise receive whole before refusing it");
    app.add_option("--max-upload-streams", o.limits.maxUploadStreams,
                   "most UploadScene streams in flight at once")
        ->capture_default_str();
    app.add_option("--upload-idle-seconds", o.limits.uploadIdleSeconds,
                   "an upload that sends nothing for this long gives its place to one that waits")
        ->capture_default_str();
    app.add_option("--upload-ttl-minutes", uploadTtlMinutes,
                   "an uploaded scene no job names for this long is removed, minutes")
        ->capture_default_str();
    app.add_option("--max-queued", o.limits.maxQueuedJobs, "most jobs waiting in the queue")
        ->capture_default_str();
    app.add_option("--max-watchers", o.limits.maxWatchersPerJob, "most watchers of one job")
        ->capture_default_str();
    app.add_option("--max-watch-streams", o.limits.maxWatchStreams,
                   "most open WatchJob streams of all jobs together")
        ->capture_default_str();
    app.add_option("--max-raw-preview-mb", rawPreviewMb,
                   "largest raw preview frame (every layer as float32 RGB) a watcher may ask "
                   "for, MiB; each job's memory estimate counts its raw frames up to this")
        ->capture_default_str();
    app.add_option("--max-depth", o.limits.maxDepth, "largest max-depth a job may ask for")
        ->capture_default_str();
    app.add_option("--max-job-memory", jobMemoryMb,
                   "largest memory estimate of one job, MiB (default: 3/4 of the machine's "
                   "memory over --max-jobs; 0: no limit)");
    app.add_option("--max-total-memory", totalMemoryMb,
                   "memory estimates of the running jobs together, MiB: a job waits in the queue "
                   "until it fits (default: 3/4 of the machine's memory; 0: no limit)");
    app.add_option("--max-store-mb", storeMb,
                   "store size beyond which uploads are refused, MiB (default: half the file "
                   "system's capacity, at most what is free there plus what the store holds; 0: "
                   "no limit)");
    app.add_option("--executor", o.cluster.executor,
                   "where jobs render: local (this process) or slurm (shards of a Slurm job "
                   "array, merged here; the store must be on a file system the nodes share)")
        ->capture_default_str();
    app.add_option("--slurm-shards", o.cluster.shards, "shards of a job under --executor slurm")
        ->capture_default_str();
    app.add_option("--slurm-cpus-per-task", o.cluster.cpusPerTask,
                   "CPUs of each shard's task (sbatch --cpus-per-task; the worker's threads)")
        ->capture_default_str();
    app.add_option("--slurm-partition", o.cluster.partition,
                   "Slurm partition of the tasks (default: the cluster's)");
    app.add_option("--slurm-worker", o.cluster.worker,
                   "the partita-local binary the tasks run (default: beside partitad)");
    app.add_option("--slurm-poll-seconds", o.cluster.pollSeconds,
                   "how often squeue and the shard files are checked")
        ->capture_default_str();
    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "partitad: %s (see --help)\n", e.what());
        return 2;
    }
    if (!(uploadMb > 0) || uploadMb > 4096) {
        std::fprintf(stderr, "partitad: --max-upload-mb must be in (0, 4096]\n");
        return 2;
    }
    o.limits.maxUploadBytes = int64_t(uploadMb * (1 << 20));
    if (!(messageMb >= 1) || messageMb > 1024) {
        std::fprintf(stderr, "partitad: --max-message-mb must be in [1, 1024]\n");
        return 2;
    }
    o.limits.maxMessageBytes = int64_t(messageMb * (1 << 20));
    if (receiveMb == -1)
        receiveMb = std::max(double(o.limits.maxReceiveBytes) / (1 << 20), 2 * messageMb);
    if (!(receiveMb >= 2 * messageMb) || receiveMb > 65536) {
        std::fprintf(stderr,
                     "partitad: --max-receive-mb must be in [2 x --max-message-mb, 65536]\n");
        return 2;
    }
    o.limits.maxReceiveBytes = int64_t(receiveMb * (1 << 20));
    if (o.limits.maxUploadStreams < 1 || o.limits.maxUploadStreams > 1024) {
        std::fprintf(stderr, "partitad: --max-upload-streams must be in [1, 1024]\n");
        return 2;
    }
    if (!(uploadTtlMinutes > 0) || uploadTtlMinutes > 7 * 24 * 60) {
        std::fprintf(stderr, "partitad: --upload-ttl-minutes must be in (0, 10080]\n");
        return 2;
    }
    o.limits.uploadTtlSeconds = uploadTtlMinutes * 60;
    if (!(o.limits.uploadIdleSeconds > 0) || o.limits.uploadIdleSeconds > 86400) {
        std::fprintf(stderr, "partitad: --upload-idle-seconds must be in (0, 86400]\n");
        return 2;
    }
    if (!(rawPreviewMb >= 0) || rawPreviewMb > 65536) {
        std::fprintf(stderr, "partitad: --max-raw-preview-mb must be in [0, 65536]\n");
        return 2;
    }
    o.limits.maxRawPreviewBytes = int64_t(rawPreviewMb * (1 << 20));
    for (double mb : {jobMemoryMb, totalMemoryMb, storeMb}) {
        if (!(mb >= 0 || mb == -1)) {
            std::fprintf(stderr,
                         "partitad: --max-job-memory, --max-total-memory and --max-store-mb must "
                         "be >= 0\n");
            return 2;
        }
    }
    o.limits.maxTotalJobMemoryBytes = totalMemoryMb < 0 ? -1 : int64_t(totalMemoryMb * (1 << 20));
    o.limits.maxJobMemoryBytes = jobMemoryMb < 0 ? -1 : int64_t(jobMemoryMb * (1 << 20));
    o.limits.maxStoreBytes = storeMb < 0 ? -1 : int64_t(storeMb * (1 << 20));
    return -1;
}

std::string finalizeServerOptions(ServerOptions& o) {
    if (o.threads < 0) return "--threads must be >= 0";
    if (o.maxJobs < 1 || o.maxJobs > 256) return "--max-jobs must be in 1..256";
    const ServiceLimits& l = o.limits;
    if (l.maxWidth < 1 || l.maxHeight < 1) return "--max-width and --max-height must be >= 1";
    if (!(l.maxSamplesPerPixel >= 1)) return "--max-spp must be >= 1";
    if (!(l.maxSeconds > 0)) return "--max-seconds must be > 0";
    if (l.maxQueuedJobs < 1) return "--max-queued must be >= 1";
    if (l.maxWatchersPerJob < 1) return "--max-watchers must be >= 1";
    if (l.maxWatchStreams < 1) return "--max-watch-streams must be >= 1";
    if (l.maxDepth < 1) return "--max-depth must be >= 1";
    if (o.store.empty()) return "--store must name a folder";
    // Absolute, so that what the daemon hands to other processes (Slurm's --output and --chdir,
    // the shard tasks' plan paths) names the same folder wherever they run (issue #25 6).
    o.store = fs::absolute(o.store);
    if (o.cluster.executor != "local" && o.cluster.executor != "slurm")
        return "--executor must be local or slurm, not '" + o.cluster.executor + "'";
    if (o.cluster.shards < 1 || o.cluster.shards > 100000)
        return "--slurm-shards must be in 1..100000";
    if (o.cluster.cpusPerTask < 1 || o.cluster.cpusPerTask > 4096)
        return "--slurm-cpus-per-task must be in 1..4096";
    if (!(o.cluster.pollSeconds >= 0.05 && o.cluster.pollSeconds <= 3600))
        return "--slurm-poll-seconds must be in [0.05, 3600]";
    // The jobs that render at once share the machine: each may have a share of 3/4 of it.
    if (o.limits.maxJobMemoryBytes < 0)
        o.limits.maxJobMemoryBytes = int64_t(physicalMemoryBytes() / 4 * 3 / uint64_t(o.maxJobs));
    if (o.limits.maxTotalJobMemoryBytes < 0)
        o.limits.maxTotalJobMemoryBytes = int64_t(physicalMemoryBytes() / 4 * 3);
    if (o.limits.maxStoreBytes < 0) o.limits.maxStoreBytes = int64_t(defaultStoreLimit(o.store));
    if (o.tlsCert.empty() != o.tlsKey.empty()) return "--tls-cert and --tls-key go together";
    bool tls = !o.tlsCert.empty(), token = !o.tokenFile.empty();
    if (!isLoopbackAddress(o.listen) && !(tls && token) && !o.insecure)
        return "refusing to listen on non-loopback address '" + o.listen +
               "' without TLS and a token: give --tls-cert, --tls-key and --token-file, or "
               "--insecure "
               "to allow it anyway";
    if (!o.http.empty()) {
        if (o.http.rfind("unix", 0) == 0 || o.http.find(':') == std::string::npos)
            return "--http takes host:port, not '" + o.http + "'";
        if (!isLoopbackAddress(o.http) && !(tls && token) && !o.insecure)
            return "refusing to serve the dashboard on non-loopback address '" + o.http +
                   "' without TLS and a token: give --tls-cert, --tls-key and --token-file, or "
                   "--insecure to allow it anyway";
    }
    if (o.sceneRoot.empty()) {
        std::error_code ec;
        if (fs::is_directory("scenes", ec)) o.sceneRoot = "scenes";
    } else {
        std::error_code ec;
        if (!fs::is_directory(o.sceneRoot, ec))
            return "--scene-root '" + o.sceneRoot.string() + "' is not a folder";
    }
    return {};
}

}  // namespace partita::server
