// Scenes uploaded ahead of their jobs (UploadScene, issue #25 7). Each is written to disk as its
// bytes arrive, in <store>/uploads/<id>/upload.pb, already in the form a job keeps its upload in
// (a serialised SceneSource: the .glb, or the .gltf and its resources), so a job that names the
// upload gets a hard link to that file, and a sweep of twenty jobs stores the scene once.
//
// Memory: an upload in flight holds one received message, never the scene; at most
// limits.maxUploadStreams are in flight (RESOURCE_EXHAUSTED beyond, at the header), and the bytes
// the header declares are reserved against the store limit before any arrive.
// A stalled upload (nothing received for limits.uploadIdleSeconds) loses its place, and its store
// reservation, to the next upload that finds every place taken; its next message is refused.
// Lifetime: an upload no job has named for limits.uploadTtlSeconds is removed (checked whenever an
// upload starts or a job names one); the staging folder is emptied when partitad starts.
#pragma once

#include <grpcpp/support/status.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "proto.h"
#include "service_limits.h"

namespace partita::server {

/// 16 lowercase hex digits: the form of an upload id (never a path).
bool isUploadId(const std::string& id);

/// A finished upload. Its folder is removed when the last holder lets go (the registry after
/// expiry, or a submission still linking it).
class StagedUpload {
  public:
    struct Resource {
        std::string uri;
        uint64_t offset = 0, size = 0;  // where its bytes lie in file()
    };
    StagedUpload(std::string id, std::filesystem::path file, pb::SceneFormat format, uint64_t bytes,
                 std::vector<Resource> resources);
    ~StagedUpload();
    StagedUpload(const StagedUpload&) = delete;
    StagedUpload& operator=(const StagedUpload&) = delete;

    const std::string& id() const { return id_; }
    /// The serialised SceneSource (kUploadFile's format).
    const std::filesystem::path& file() const { return file_; }
    /// The files' bytes together, as the header declared them.
    uint64_t bytes() const { return bytes_; }
    /// The scene as a job's record keeps it: glb or gltf with resource names, no bytes.
    pb::SceneSource shape() const;
    /// The bytes of resource `uri`, read from file(). Throws SceneLoadError when there is none.
    std::vector<uint8_t> readResource(const std::string& uri) const;

  private:
    std::string id_;
    std::filesystem::path file_;
    pb::SceneFormat format_;
    uint64_t bytes_;
    std::vector<Resource> resources_;
};

class UploadStaging;

/// One upload in flight: append() the bytes as they arrive, then finish(). Destroyed unfinished
/// (a client that went away, an error), it removes what it wrote and frees its admission.
class UploadWriter {
  public:
    ~UploadWriter();
    UploadWriter(const UploadWriter&) = delete;
    UploadWriter& operator=(const UploadWriter&) = delete;

    /// INVALID_ARGUMENT for bytes beyond the declared sizes; INTERNAL when the disk refuses.
    grpc::Status append(const std::string& data);
    /// INVALID_ARGUMENT when fewer bytes arrived than declared; else publishes the upload.
    grpc::Status finish(pb::UploadSceneResponse& out);

  private:
    friend class UploadStaging;
    /// The wire form of the SceneSource, as pieces: a field prefix (tags and lengths, protobuf's
    /// encoding) before each file's bytes.
    struct Segment {
        std::string prefix;
        uint64_t size = 0;
    };
    UploadWriter(UploadStaging& staging, std::string id, const pb::UploadHeader& header,
                 uint64_t reserved);
    grpc::Status openFile();
    grpc::Status write(const char* data, size_t size);

    UploadStaging& staging_;
    std::string id_;
    pb::SceneFormat format_;
    uint64_t declared_ = 0, reserved_ = 0;
    std::vector<Segment> segments_;
    std::vector<StagedUpload::Resource> resources_;
    size_t segment_ = 0;          // the file being received
    uint64_t leftInSegment_ = 0;  // its bytes still to come
    uint64_t written_ = 0;        // bytes of upload.pb so far
    int fd_ = -1;
    bool finished_ = false;
    // Guarded by the staging's mutex:
    std::chrono::steady_clock::time_point lastActivity_;
    bool abandoned_ = false;  // its place was given to another upload
    bool finishing_ = false;  // past its last byte: never abandoned
};

class UploadStaging {
  public:
    /// Store bytes are reserved and released through these (JobManager's store accounting, so
    /// that uploads in flight and inline uploads share the store limit).
    using Reserve = std::function<grpc::Status(uint64_t bytes)>;
    using Release = std::function<void(uint64_t bytes)>;

    /// Empties <storeDir>/uploads (uploads do not outlive a restart).
    UploadStaging(const std::filesystem::path& storeDir, const ServiceLimits& limits,
                  Reserve reserve, Release release);

    /// Admits an upload: checks the header (format, sizes against --max-upload-mb, resource
    /// uris), the uploads in flight (--max-upload-streams) and the store's room.
    grpc::Status begin(const pb::UploadHeader& header, std::unique_ptr<UploadWriter>& out);

    /// The finished upload `id`, or NOT_FOUND (expired, never finished, or from before a
    /// restart). Naming it keeps it alive for another TTL.
    grpc::Status find(const std::string& id, std::shared_ptr<StagedUpload>& out);

    size_t stagedCount() const;

  private:
    friend class UploadWriter;
    std::filesystem::path folder(const std::string& id) const { return dir_ / id; }
    void publish(std::shared_ptr<StagedUpload> upload);
    /// A writer is done, finished or not (null: admission failed before it existed).
    void ended(UploadWriter* writer, uint64_t reserved);
    /// A writer received something (or, `finishing`, its last byte): ABORTED when its place was
    /// given away meanwhile.
    grpc::Status touch(UploadWriter& writer, bool finishing = false);
    /// Every place is taken: takes back those of writers idle for uploadIdleSeconds; their ids
    /// and reservations in `freed`, for the caller to release outside the lock.
    void reclaimIdleLocked(std::chrono::steady_clock::time_point now,
                           std::vector<std::pair<std::string, uint64_t>>& freed);
    void expireLocked(std::chrono::steady_clock::time_point now);
    std::string newId();

    std::filesystem::path dir_;
    const ServiceLimits& limits_;
    Reserve reserve_;
    Release release_;
    mutable std::mutex mutex_;
    int inFlight_ = 0;
    std::set<UploadWriter*> active_;  // admitted writers that still hold their place
    struct Entry {
        std::shared_ptr<StagedUpload> upload;
        std::chrono::steady_clock::time_point lastUsed;
    };
    std::map<std::string, Entry> staged_;
};

}  // namespace partita::server
