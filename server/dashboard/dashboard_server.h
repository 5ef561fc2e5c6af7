// partitad --http ADDR: the browser dashboard (issue #26). An HTTP server (cpp-httplib, TLS when
// the daemon has a certificate) on its own threads, in front of the same JobApi as the gRPC
// service: one job system, one store. It serves
//   GET  /, /job?id=ID, /static/NAME       the pages (assets.h: from memory, never from disk)
//   GET  /api/info, /api/scenes            server, algorithms with their parameters; scenes
//   GET  /api/jobs, /api/jobs/ID           jobs (proto3 JSON of partita.v1.Job)
//   POST /api/jobs                         submit a JobSpec (JSON; an upload's .glb base64)
//   POST /api/jobs/ID/cancel, DELETE /api/jobs/ID
//   GET  /api/jobs/ID/events               server-sent events: state, progress, frame (PNGs)
//   GET  /api/jobs/ID/result.exr|preview.png|metadata.json
// Refusals are the gRPC API's, as HTTP statuses with a JSON body (http_wire.h); who may call is
// http_access.h. Each event stream holds one HTTP thread: streams are limited to leave threads
// for the rest, and a stream whose browser stops reading ends after the write timeout.
#pragma once

#include <atomic>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include "auth.h"
#include "http_access.h"
#include "job_api.h"

namespace httplib {
class Server;
}

namespace partita::server::dashboard {

struct DashboardOptions {
    std::string address;                    // host:port (port 0: any free port)
    std::filesystem::path tlsCert, tlsKey;  // both or neither
    int maxEventStreams = 24;               // open /events streams together
    int writeTimeoutSeconds = 5;            // a browser that stops reading is dropped after it
};

class DashboardServer {
  public:
    DashboardServer(JobApi& api, const TokenAuth& auth, DashboardOptions options);
    ~DashboardServer();

    /// Binds and starts serving on a thread of its own. Returns the bound port; throws
    /// std::runtime_error when it cannot listen or the TLS files are unusable.
    int start();
    /// Stops serving: open event streams end, requests in flight finish. Idempotent.
    void stop();

  private:
    /// The largest body held whole (every route but /api/uploads, which streams).
    size_t jsonBodyLimit() const;
    void addRoutes();
    void addPageRoutes();
    void addJobRoutes();
    void addEventRoute();
    void addResultRoute();

    JobApi& api_;
    const DashboardOptions options_;
    HttpAccess access_;
    std::unique_ptr<httplib::Server> server_;
    std::thread thread_;
    std::atomic<int> openStreams_{0};
    std::atomic<bool> stopping_{false};
};

}  // namespace partita::server::dashboard
