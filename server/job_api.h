// What a client may ask of the daemon, whatever the transport: submit, look up, list, cancel and
// delete jobs, find their result files, list scenes, describe the server. The gRPC service
// (partita_service.h) and the HTTP dashboard (dashboard/) both call this, so the two faces share
// one job system, one store and the same validation; each only maps requests, answers and
// status codes to its wire.
#pragma once

#include <grpcpp/support/status.h>

#include <filesystem>
#include <memory>
#include <string>

#include "job_manager.h"
#include "proto.h"
#include "scene_source.h"
#include "service_limits.h"
#include "upload_staging.h"

namespace partita::server {

class JobApi {
  public:
    /// `uploads` may be null: then a job cannot name a staged upload (scene.upload_id).
    JobApi(JobManager& jobs, const SceneSource& scenes, const ServiceLimits& limits,
           UploadStaging* uploads = nullptr)
        : jobs_(jobs), scenes_(scenes), limits_(limits), uploads_(uploads) {}

    /// Validates the spec (fields, parameters, scene, environment image) and queues the job.
    grpc::Status submit(const pb::JobSpec& spec, pb::Job& out);
    /// Admits an upload (UploadScene's first message): see UploadStaging::begin.
    grpc::Status beginUpload(const pb::UploadHeader& header, std::unique_ptr<UploadWriter>& out);
    /// NOT_FOUND naming the id when there is no such job.
    grpc::Status get(const std::string& id, pb::Job& out) const;
    std::shared_ptr<Job> find(const std::string& id) const { return jobs_.find(id); }
    grpc::Status list(const pb::ListJobsRequest& request, pb::ListJobsResponse& out) const;
    grpc::Status cancel(const std::string& id, pb::Job& out) { return jobs_.cancel(id, out); }
    grpc::Status remove(const std::string& id) { return jobs_.remove(id); }
    /// The file of a DONE job's result of `kind`, or why there is none (NOT_FOUND,
    /// INVALID_ARGUMENT for an unknown kind, FAILED_PRECONDITION before DONE).
    grpc::Status resultFile(const std::string& id, pb::ResultKind kind,
                            std::filesystem::path& file) const;
    /// OK, or RESOURCE_EXHAUSTED when the job's raw preview frames (every layer as float32 RGB)
    /// would be larger than the server's limit (--max-raw-preview-mb): its memory estimate
    /// counts raw frames only up to it.
    grpc::Status checkRawPreviews(const Job& job) const;
    void listScenes(pb::ListScenesResponse& out) const;
    /// Version, threads, limits, and every algorithm with its declared parameters.
    void serverInfo(pb::ServerInfo& out) const;

    const ServiceLimits& limits() const { return limits_; }

  private:
    /// submit() of a job whose scene is a staged upload: the job's record names the upload's
    /// files (as an inline upload's would) and its folder gets a hard link to them.
    grpc::Status submitStaged(const pb::JobSpec& spec, pb::Job& out);

    JobManager& jobs_;
    const SceneSource& scenes_;
    const ServiceLimits& limits_;
    UploadStaging* uploads_;
};

/// NOT_FOUND: "no job '<id>'" (the id quoted safely).
grpc::Status unknownJob(const std::string& id);

}  // namespace partita::server
