// Runs one job: LOADING (read the scene, build the BVH; the cancel flag is checked between the
// steps), then the algorithm on the shared thread pool (PREPASS/RENDERING follow its progress
// phases), then the result files, the final frame and DONE. A scene that fails to load, or any
// other error, fails the job with one line; a cancel ends it CANCELLED, or QUEUED again when the
// cancel came from a daemon shutdown.
#pragma once

#include "cluster_options.h"
#include "job.h"
#include "job_store.h"
#include "scene_source.h"
#include "service_limits.h"
#include "thread_pool.h"

namespace partita::server {

struct RunContext {
    JobStore& store;
    const SceneSource& scenes;
    const ServiceLimits& limits;
    ThreadPool& pool;
    const ClusterOptions& cluster;  // --executor local|slurm
};

/// The file name of an uploaded scene inside the job's folder (a serialized SceneSource).
inline constexpr const char* kUploadFile = "scene.upload";
inline constexpr const char* kResultExr = "result.exr";
inline constexpr const char* kResultPng = "preview.png";
inline constexpr const char* kResultMetadata = "metadata.json";

/// Deletes a job's uploaded scene once the job has finished (it is kept only so that a queued or
/// re-queued job can run after a restart).
void removeUpload(const JobStore& store, const std::string& id);

/// Runs `job` (which must be QUEUED) to the end. Never throws.
void runJob(Job& job, const RunContext& context, const Job::Persist& persist);

}  // namespace partita::server
