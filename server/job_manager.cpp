#include "job_manager.h"

#include <spdlog/spdlog.h>

#include <random>

#include "file_io.h"
#include "job_runner.h"
#include "parameter_wire.h"
#include "store_usage.h"
#include "stored_job.h"
#include "text.h"

namespace partita::server {

namespace fs = std::filesystem;

JobManager::JobManager(JobStore& store, const SceneSource& scenes, const ServiceLimits& limits,
                       int threads, int maxJobs, const ClusterOptions& cluster)
    : store_(store),
      scenes_(scenes),
      limits_(limits),
      cluster_(cluster),
      maxJobs_(maxJobs),
      pool_(threads) {
    // Running jobs together stay within the total (never below one job's limit, so that any
    // accepted job can run): a job waits in the queue until it fits next to the running ones.
    if (limits_.maxTotalJobMemoryBytes > 0)
        memoryPool_ = uint64_t(std::max(limits_.maxTotalJobMemoryBytes, limits_.maxJobMemoryBytes));
    persist_ = [this](const Job& job, const pb::Job& next, const std::string& note) {
        store_.update(toStored(next, job.sequence()), note);
    };
}

JobManager::~JobManager() { shutdown(); }

void JobManager::recover() {
    store_.removeOrphanFolders();
    size_t queued = 0, requeued = 0, finished = 0;
    for (const StoredJob& stored : store_.loadAll()) {
        auto job = std::make_shared<Job>(fromStored(stored), stored.sequence);
        pb::JobState state = job->state();
        if (isActive(state)) {
            std::string note =
                "re-queued after restart: partitad stopped while the job was " + stateName(state);
            pb::Job record = job->snapshot();
            std::map<std::string, double> stats(record.stats().begin(), record.stats().end());
            stats["requeued"] += 1;
            job->transition(pb::JOB_STATE_QUEUED, "", persist_, note, &stats);
            spdlog::warn("{} {}", job->tag(), note);
            state = pb::JOB_STATE_QUEUED;
            ++requeued;
        }
        if (state == pb::JOB_STATE_QUEUED) {
            memory_[job.get()] = estimateStored(*job);
            queue_.insert(job);
            ++queued;
        } else {
            ++finished;
            if (state == pb::JOB_STATE_DONE)
                job->keepFinalFrameOnDisk(store_.jobDir(job->id()) / kResultExr);
        }
        jobs_[job->id()] = job;
    }
    spdlog::info("job store '{}': {} finished jobs, {} queued ({} of them re-queued)",
                 store_.dir().string(), finished, queued, requeued);
}

void JobManager::start() {
    std::lock_guard lock(mutex_);
    if (started_) return;
    started_ = true;
    {
        // recover() takes no lock of its own; nothing else runs yet.
        recover();
    }
    for (int i = 0; i < maxJobs_; ++i) runners_.emplace_back([this] { runnerLoop(); });
}

void JobManager::shutdown() {
    {
        std::lock_guard lock(mutex_);
        if (stopping_ && runners_.empty()) return;
        stopping_ = true;
        for (const auto& job : running_) job->requestCancel(CancelReason::Shutdown);
    }
    cv_.notify_all();
    for (auto& t : runners_) t.join();
    runners_.clear();
    std::vector<std::shared_ptr<Job>> jobs;
    {
        std::lock_guard lock(mutex_);
        for (const auto& [id, job] : jobs_) jobs.push_back(job);
    }
    grpc::Status closing(
        grpc::StatusCode::UNAVAILABLE,
        "partitad is shutting down; queued and interrupted jobs run again after it restarts");
    for (const auto& job : jobs) job->closeWatchers(closing);
    store_.checkpoint();
}

namespace {

/// A job's own name for a staged upload's file: a hard link (the store holds the bytes once),
/// or a copy where the file system has no hard links.
void linkStagedUpload(const StagedUpload& staged, const fs::path& to) {
    std::error_code ec;
    fs::create_hard_link(staged.file(), to, ec);
    if (ec) fs::copy_file(staged.file(), to, ec);
    if (ec) throw std::runtime_error("cannot link the staged upload: " + ec.message());
}

}  // namespace

// The form JobStore accepts (isJobId): 12 lowercase hex digits.
std::string JobManager::newId() const {
    static std::mt19937_64 rng(std::random_device{}());
    for (;;) {
        char buf[17];
        std::snprintf(buf, sizeof buf, "%012llx",
                      static_cast<unsigned long long>(rng() & 0xffffffffffffULL));
        std::string id(buf);
        if (!jobs_.count(id) && !reserved_.count(id)) return id;
    }
}

MemoryEstimate JobManager::estimate(const pb::JobSpec&, const ValidatedSpec& v,
                                    uint64_t sceneBytes) const {
    return estimateJobMemory(v.algorithm, v.settings, sceneBytes, pool_.threadCount(),
                             v.environment,
                             uint64_t(std::max<int64_t>(0, limits_.maxRawPreviewBytes)));
}

uint64_t JobManager::estimateStored(const Job& job) const {
    ValidatedSpec v;
    if (!settingsFromSpec(job.spec(), limits_, v).ok()) return 0;  // it fails when it runs
    uint64_t sceneBytes = 0;
    std::error_code ec;
    if (job.spec().scene().has_scene_name())
        sceneBytes = scenes_.sceneBytes(job.spec().scene().scene_name());
    else if (auto size = fs::file_size(store_.jobDir(job.id()) / kUploadFile, ec); !ec)
        sceneBytes = size;
    return estimate(job.spec(), v, sceneBytes).bytes;
}

grpc::Status JobManager::reserveStore(uint64_t bytes) {
    if (limits_.maxStoreBytes <= 0) return grpc::Status::OK;
    uint64_t used = folderBytes(store_.dir());
    if (used + pendingUploadBytes_ + bytes > uint64_t(limits_.maxStoreBytes))
        return {grpc::StatusCode::RESOURCE_EXHAUSTED,
                "the job store is full: it holds " +
                    humanBytes(double(used + pendingUploadBytes_)) + " and this upload has " +
                    humanBytes(double(bytes)) + ", over its limit of " +
                    humanBytes(double(limits_.maxStoreBytes)) +
                    " (--max-store-mb); delete finished jobs or wait for queued ones"};
    pendingUploadBytes_ += bytes;
    return grpc::Status::OK;
}

bool JobManager::headFits() const {
    if (memoryPool_ == 0 || running_.empty()) return true;
    auto it = memory_.find(queue_.begin()->get());
    uint64_t need = it == memory_.end() ? 0 : it->second;
    return runningMemory_ + need <= memoryPool_;
}

grpc::Status JobManager::reserveUploadBytes(uint64_t bytes) {
    std::lock_guard lock(mutex_);
    return reserveStore(bytes);
}

void JobManager::releaseUploadBytes(uint64_t bytes) {
    std::lock_guard lock(mutex_);
    pendingUploadBytes_ -= bytes;
}

grpc::Status JobManager::submit(const pb::JobSpec& spec, const ValidatedSpec& validated,
                                pb::Job& out, const StagedUpload* staged) {
    const bool upload = !spec.scene().has_scene_name();
    const uint64_t sceneBytes = staged   ? staged->bytes()
                                : upload ? SceneSource::uploadBytes(spec.scene())
                                         : scenes_.sceneBytes(spec.scene().scene_name());
    // What this submission adds to the store: an inline upload's bytes (a staged one is there).
    const uint64_t uploadBytes = upload && !staged ? sceneBytes : 0;
    const MemoryEstimate memory = estimate(spec, validated, sceneBytes);
    if (limits_.maxJobMemoryBytes > 0 && memory.bytes > uint64_t(limits_.maxJobMemoryBytes))
        return {grpc::StatusCode::RESOURCE_EXHAUSTED,
                "the job needs an estimated " + humanBytes(double(memory.bytes)) + " of memory (" +
                    memory.breakdown + "), over this server's limit of " +
                    humanBytes(double(limits_.maxJobMemoryBytes)) +
                    " per job (--max-job-memory); lower the resolution or max_type_layers"};
    std::string id;
    {
        std::lock_guard lock(mutex_);
        if (stopping_) return {grpc::StatusCode::UNAVAILABLE, "partitad is shutting down"};
        if (int(queue_.size() + reserved_.size()) >= limits_.maxQueuedJobs)
            return {grpc::StatusCode::RESOURCE_EXHAUSTED,
                    "the queue is full: " + std::to_string(queue_.size()) +
                        " jobs are waiting, the limit of this server (--max-queued)"};
        if (uploadBytes > 0)
            if (grpc::Status s = reserveStore(uploadBytes); !s.ok()) return s;
        id = newId();
        reserved_.insert(id);
    }
    pb::Job record;
    record.set_id(id);
    *record.mutable_spec() = withoutSceneBytes(spec);
    // What the job runs with, defaults filled in: a run after a restart uses the same values.
    storeResolvedParameters(*AlgorithmRegistry::instance().find(validated.algorithm),
                            validated.settings, *record.mutable_spec());
    record.set_state(pb::JOB_STATE_QUEUED);
    record.set_created_unix_ms(nowUnixMs());
    std::shared_ptr<Job> job;
    try {
        if (upload) {
            // The upload is kept with the job so that it can run (again) after a restart.
            fs::create_directories(store_.jobDir(id));
            if (staged)
                linkStagedUpload(*staged, store_.jobDir(id) / kUploadFile);
            else  // serialised straight into the file: no second copy of the upload in memory
                partita::writeFileAtomic(store_.jobDir(id) / kUploadFile, [&](int fd) {
                    return spec.scene().SerializeToFileDescriptor(fd);
                });
        }
        int64_t sequence = store_.nextSequence();
        store_.insert(toStored(record, sequence), "submitted");
        job = std::make_shared<Job>(record, sequence);
    } catch (const std::exception& e) {
        std::error_code ec;
        fs::remove_all(store_.jobDir(id), ec);
        std::lock_guard lock(mutex_);
        reserved_.erase(id);
        pendingUploadBytes_ -= uploadBytes;
        spdlog::error("[job {}] could not be stored: {}", id, e.what());
        return {grpc::StatusCode::INTERNAL,
                std::string("the job could not be stored: ") + e.what()};
    }
    // Logged before a runner can take it, so that "queued" comes before "loading".
    spdlog::info("{} queued: {} on '{}', priority {}, memory estimate {}", job->tag(),
                 quoteInput(validated.algorithm), quoteInput(sceneLabel(spec), 200),
                 spec.priority(), humanBytes(double(memory.bytes)));
    {
        std::lock_guard lock(mutex_);
        reserved_.erase(id);
        pendingUploadBytes_ -= uploadBytes;
        jobs_[id] = job;
        memory_[job.get()] = memory.bytes;
        queue_.insert(job);
    }
    cv_.notify_all();
    out = job->snapshot();
    return grpc::Status::OK;
}

std::shared_ptr<Job> JobManager::find(const std::string& id) const {
    std::lock_guard lock(mutex_);
    auto it = jobs_.find(id);
    return it == jobs_.end() ? nullptr : it->second;
}

grpc::Status JobManager::cancel(const std::string& id, pb::Job& out) {
    std::lock_guard lock(mutex_);
    auto it = jobs_.find(id);
    if (it == jobs_.end()) return {grpc::StatusCode::NOT_FOUND, "no job '" + quoteInput(id) + "'"};
    const auto& job = it->second;
    if (queue_.erase(job)) {
        memory_.erase(job.get());
        try {
            job->transition(pb::JOB_STATE_CANCELLED, "", persist_, "cancelled while queued");
        } catch (const std::exception& e) {
            queue_.insert(job);
            return {grpc::StatusCode::INTERNAL,
                    std::string("could not record the cancel: ") + e.what()};
        }
        removeUpload(store_, job->id());
        spdlog::info("{} cancelled while queued", job->tag());
    } else {
        pb::JobState state = job->state();
        if (state == pb::JOB_STATE_DONE || state == pb::JOB_STATE_FAILED)
            return {grpc::StatusCode::FAILED_PRECONDITION,
                    "job " + id + " has already finished (" + stateName(state) + ")"};
        if (state != pb::JOB_STATE_CANCELLED && !job->cancelRequested()) {
            job->requestCancel(CancelReason::User);
            spdlog::info("{} cancel requested while {}", job->tag(), stateName(state));
        }
    }
    out = job->snapshot();
    return grpc::Status::OK;
}

grpc::Status JobManager::remove(const std::string& id) {
    std::shared_ptr<Job> job;
    {
        std::lock_guard lock(mutex_);
        auto it = jobs_.find(id);
        if (it == jobs_.end())
            return {grpc::StatusCode::NOT_FOUND, "no job '" + quoteInput(id) + "'"};
        pb::JobState state = it->second->state();
        bool cancelling = it->second->cancelReason() == CancelReason::User;
        if (!isTerminal(state) && !cancelling)
            return {grpc::StatusCode::FAILED_PRECONDITION,
                    "job " + id + " is " + stateName(state) + ": cancel it before deleting it"};
        job = it->second;
        jobs_.erase(it);
        if (!isTerminal(state)) {
            // Cancelled but still stopping: its runner removes the record when the render ends.
            deleting_.insert(id);
            job->closeWatchers({grpc::StatusCode::NOT_FOUND, "job " + id + " was deleted"});
            spdlog::info("{} deleted while cancelling; removed from the store once it stops",
                         job->tag());
            return grpc::Status::OK;
        }
    }
    job->closeWatchers({grpc::StatusCode::NOT_FOUND, "job " + id + " was deleted"});
    try {
        store_.remove(id);
    } catch (const std::exception& e) {
        spdlog::error("{} could not be deleted from the store: {}", job->tag(), e.what());
        return {grpc::StatusCode::INTERNAL, std::string("could not delete the job: ") + e.what()};
    }
    spdlog::info("{} deleted", job->tag());
    return grpc::Status::OK;
}

std::vector<pb::Job> JobManager::list(const std::string& label, const std::set<int>& states) const {
    std::vector<std::shared_ptr<Job>> jobs;
    {
        std::lock_guard lock(mutex_);
        for (const auto& [id, job] : jobs_) jobs.push_back(job);
    }
    std::sort(jobs.begin(), jobs.end(),
              [](const auto& a, const auto& b) { return a->sequence() < b->sequence(); });
    std::vector<pb::Job> out;
    for (const auto& job : jobs) {
        if (!label.empty() && job->spec().label() != label) continue;
        pb::Job snapshot = job->snapshot();
        if (!states.empty() && !states.count(int(snapshot.state()))) continue;
        out.push_back(std::move(snapshot));
    }
    return out;
}

void JobManager::removeDeleted(const Job& job) {
    try {
        store_.remove(job.id());
        spdlog::info("{} removed from the store (deleted while cancelling)", job.tag());
    } catch (const std::exception& e) {
        spdlog::error("{} could not be deleted from the store: {}", job.tag(), e.what());
    }
}

void JobManager::runnerLoop() {
    RunContext context{store_, scenes_, limits_, pool_, cluster_};
    for (;;) {
        std::shared_ptr<Job> job;
        {
            std::unique_lock lock(mutex_);
            cv_.wait(lock, [&] { return stopping_ || (!queue_.empty() && headFits()); });
            if (stopping_) return;
            job = *queue_.begin();
            queue_.erase(queue_.begin());
            running_.insert(job);
            runningMemory_ += memory_[job.get()];
        }
        runJob(*job, context, persist_);
        bool deleted = false;
        {
            std::lock_guard lock(mutex_);
            running_.erase(job);
            runningMemory_ -= memory_[job.get()];
            memory_.erase(job.get());
            deleted = deleting_.erase(job->id()) > 0;
        }
        cv_.notify_all();  // its memory is free for the next job
        if (deleted) removeDeleted(*job);
    }
}

}  // namespace partita::server
