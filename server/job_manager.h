// The jobs of one daemon: a priority queue (higher priority first, then submission order),
// `maxJobs` runner threads that take jobs from it, and one core ThreadPool that every running
// job renders on. Jobs are persisted in the JobStore at each transition; at start-up the store
// is read back: finished jobs are kept, queued ones queued again, and jobs that were running
// when the daemon stopped (even by kill -9) go back to QUEUED with a note.
#pragma once

#include <grpcpp/support/status.h>

#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "cluster_options.h"
#include "job.h"
#include "job_memory.h"
#include "job_store.h"
#include "scene_source.h"
#include "service_limits.h"
#include "thread_pool.h"
#include "upload_staging.h"
#include "validation.h"

namespace partita::server {

class JobManager {
  public:
    JobManager(JobStore& store, const SceneSource& scenes, const ServiceLimits& limits, int threads,
               int maxJobs, const ClusterOptions& cluster = {});
    ~JobManager();  // shuts down if still running

    /// Reads the store back (see above) and starts the runner threads.
    void start();
    /// Stops taking jobs, cancels the running ones (they go back to QUEUED in the store), waits
    /// for the runners, and ends every watch with UNAVAILABLE. Idempotent.
    void shutdown();

    /// Queues a validated job. `spec` carries the scene (an upload is written to the store
    /// first). RESOURCE_EXHAUSTED when the queue is full, when the job's memory estimate is over
    /// --max-job-memory, or when an upload would take the store over --max-store-mb;
    /// UNAVAILABLE while shutting down. With `staged`, the scene is that staged upload (spec
    /// names its files): the job's folder gets a hard link to it, and no store bytes are
    /// reserved (they are in the store already).
    grpc::Status submit(const pb::JobSpec& spec, const ValidatedSpec& validated, pb::Job& out,
                        const StagedUpload* staged = nullptr);
    /// Store bytes for an upload in flight, against --max-store-mb with every other pending
    /// upload (RESOURCE_EXHAUSTED when they do not fit); release them when it ends.
    grpc::Status reserveUploadBytes(uint64_t bytes);
    void releaseUploadBytes(uint64_t bytes);
    std::shared_ptr<Job> find(const std::string& id) const;
    /// A queued job is cancelled at once; a running one is flagged and ends shortly.
    grpc::Status cancel(const std::string& id, pb::Job& out);
    /// Deletes a finished job and its files; FAILED_PRECONDITION while it is queued or running.
    /// A job whose cancel was requested but that has not stopped yet is deleted too: it is gone
    /// from the listing at once, and its record and files are removed when its render stops.
    grpc::Status remove(const std::string& id);
    /// Jobs in submission order, optionally only those with `label` / in `states`.
    std::vector<pb::Job> list(const std::string& label, const std::set<int>& states) const;

    /// The folder holding a job's result files.
    std::filesystem::path resultDir(const std::string& id) const { return store_.jobDir(id); }
    int threads() const { return pool_.threadCount(); }
    int maxJobs() const { return maxJobs_; }
    const Job::Persist& persist() const { return persist_; }

  private:
    struct QueueOrder {
        bool operator()(const std::shared_ptr<Job>& a, const std::shared_ptr<Job>& b) const {
            if (a->priority() != b->priority()) return a->priority() > b->priority();
            return a->sequence() < b->sequence();
        }
    };

    void recover();
    void runnerLoop();
    /// The memory estimate of a job (its scene looked up in the store or the scene root).
    MemoryEstimate estimate(const pb::JobSpec& spec, const ValidatedSpec& v,
                            uint64_t sceneBytes) const;
    uint64_t estimateStored(const Job& job) const;
    /// OK, or RESOURCE_EXHAUSTED when an upload of `bytes` would take the store over its limit.
    /// Reserves the bytes (in pendingUploadBytes_) when OK; with mutex_ held.
    grpc::Status reserveStore(uint64_t bytes);
    /// With mutex_ held: whether the first queued job fits next to the running ones.
    bool headFits() const;
    /// Removes a job deleted while it was cancelling, once its runner is done with it.
    void removeDeleted(const Job& job);
    std::string newId() const;  // with mutex_ held

    JobStore& store_;
    const SceneSource& scenes_;
    const ServiceLimits& limits_;
    const ClusterOptions cluster_;
    const int maxJobs_;
    ThreadPool pool_;
    Job::Persist persist_;

    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::map<std::string, std::shared_ptr<Job>> jobs_;
    std::set<std::shared_ptr<Job>, QueueOrder> queue_;
    std::set<std::shared_ptr<Job>> running_;  // taken from the queue by a runner
    std::set<std::string> reserved_;          // ids of submissions being stored
    std::map<const Job*, uint64_t> memory_;   // memory estimate of each queued or running job
    uint64_t runningMemory_ = 0;              // the sum over running_
    uint64_t memoryPool_ = 0;                 // what running jobs may use together (0: no limit)
    uint64_t pendingUploadBytes_ = 0;         // uploads being written to the store
    std::set<std::string> deleting_;          // deleted while cancelling: removed when they stop
    bool stopping_ = false, started_ = false;
    std::vector<std::thread> runners_;
};

}  // namespace partita::server
