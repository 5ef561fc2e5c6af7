// What the service tests share: a temporary folder, the real partitad started as a child process,
// and small client helpers over the generated stub.
#pragma once

#if __has_include("partita/v1/partita.grpc.pb.h")
#include "partita/v1/partita.grpc.pb.h"
#else
#include "partita.grpc.pb.h"
#endif

#include <grpcpp/grpcpp.h>
#include <sys/types.h>

#include <csignal>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "temp_dir.h"

namespace partita::test {

namespace pb = ::partita::v1;
namespace fs = std::filesystem;

/// partitad as a child process on 127.0.0.1 with port 0 and --port-file.
class Daemon {
  public:
    /// Starts partitad with `--listen 127.0.0.1:0 --store <store> --scene-root <scenes>
    /// --threads 2 --port-file ...` plus `extra` (which may give its own --listen). Fails the test
    /// (ADD_FAILURE) if it does not come up.
    Daemon(const fs::path& store, std::vector<std::string> extra = {},
           const fs::path& sceneRoot = PARTITA_SCENES_DIR);
    ~Daemon();  // SIGKILL if still running
    Daemon(const Daemon&) = delete;
    Daemon& operator=(const Daemon&) = delete;

    bool running() const { return port_ > 0 && pid_ > 0; }
    int port() const { return port_; }
    pid_t pid() const { return pid_; }
    std::string address() const { return "127.0.0.1:" + std::to_string(port_); }
    std::shared_ptr<grpc::Channel> channel() const;
    std::unique_ptr<pb::Partita::Stub> stub() const { return pb::Partita::NewStub(channel()); }
    /// What the daemon wrote to stdout/stderr so far.
    std::string log() const;

    /// Sends `signal` and waits for the exit; returns the exit code (128 + n when killed by n).
    int stop(int signal = SIGTERM, std::chrono::seconds timeout = std::chrono::seconds(20));

  private:
    pid_t pid_ = -1;
    int port_ = 0;
    TempDir runDir_;  // port file and log
};

/// Runs partitad with `args` (no defaults added), waits for it to exit (at most `timeout`) and
/// returns {exit code, its stderr+stdout}. For start-up errors.
std::pair<int, std::string> runPartitad(const std::vector<std::string>& args,
                                        std::chrono::seconds timeout = std::chrono::seconds(20));

/// A context with a deadline (and the token, when given).
std::unique_ptr<grpc::ClientContext> context(
    std::chrono::milliseconds deadline = std::chrono::seconds(60), const std::string& token = {});

/// A job on a named scene: width x height, spp samples per pixel of `pt`, the given seed.
pb::JobSpec sceneSpec(const std::string& scene, int width, int height, double spp,
                      uint64_t seed = 1);

struct Submitted {
    grpc::Status status;
    std::string id;
};
Submitted submit(pb::Partita::Stub& stub, const pb::JobSpec& spec, const std::string& token = {});

struct Uploaded {
    grpc::Status status;
    std::string id;
};
/// One UploadScene stream: `header` (unless sendHeader is false), then each of `pieces` as a
/// data message.
Uploaded sendUpload(pb::Partita::Stub& stub, const pb::UploadHeader& header,
                    const std::vector<std::string>& pieces, bool sendHeader = true);
/// Streams the upload `source` holds (glb, or gltf with resources) in pieces of `pieceBytes`,
/// which run across the files' boundaries as a client may send them.
Uploaded upload(pb::Partita::Stub& stub, const pb::SceneSource& source,
                size_t pieceBytes = size_t(1) << 20);

/// Everything a watch received until the stream ended.
struct WatchLog {
    std::vector<pb::JobEvent> events;
    grpc::Status status;
    std::vector<pb::JobState> states() const;
    std::vector<const pb::PreviewFrame*> frames() const;
    std::optional<pb::Job> last() const;  // the last state event
};
/// A WatchJob request for job `id`, with preview frames (PNG) and raw float pixels as asked.
pb::WatchJobRequest watchRequest(const std::string& id, bool previews = false, bool raw = false);
WatchLog watch(pb::Partita::Stub& stub, const std::string& id, bool previews = false,
               bool raw = false, std::chrono::milliseconds deadline = std::chrono::seconds(90));

/// Polls GetJob until the job is in `state` (true) or the timeout passes (false).
bool waitForState(pb::Partita::Stub& stub, const std::string& id, pb::JobState state,
                  std::chrono::milliseconds timeout = std::chrono::seconds(60));
/// Polls until the job is DONE, FAILED or CANCELLED; returns the job (state UNSPECIFIED on
/// timeout).
pb::Job waitForEnd(pb::Partita::Stub& stub, const std::string& id,
                   std::chrono::milliseconds timeout = std::chrono::seconds(60));

struct Fetched {
    grpc::Status status;
    std::string bytes;
    bool chunksConsistent = true;  // offsets contiguous, total_size constant and right
    size_t chunks = 0;
};
Fetched fetch(pb::Partita::Stub& stub, const std::string& id, pb::ResultKind kind);

/// A GLB of a regular grid of `n` x `n` vertices (2 (n-1)^2 triangles) with a camera and an
/// emissive quad: large enough for loading to take a while.
std::string makeGridGlb(int n);
/// A .gltf (JSON) with one triangle whose buffer has the given uri.
std::string gltfWithBufferUri(const std::string& uri, size_t byteLength = 36);

std::string readFile(const fs::path& path);
/// GetServerInfo (the call is expected to succeed).
pb::ServerInfo serverInfo(pb::Partita::Stub& stub);
/// A /proc/<pid>/status field in KiB ("VmRSS", "VmHWM"); 0 when absent.
uint64_t procStatusKiB(pid_t pid, const std::string& field);
void writeFile(const fs::path& path, const std::string& bytes);

}  // namespace partita::test
