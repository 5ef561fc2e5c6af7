#include "partita_service.h"

#include <spdlog/spdlog.h>

#include "algorithm.h"
#include "job_runner.h"
#include "result_stream.h"
#include "validation.h"
#include "watch_session.h"

#ifndef PARTITA_VERSION
#define PARTITA_VERSION "0.0.0"
#endif

namespace partita::server {

namespace {

grpc::ServerUnaryReactor* finish(grpc::CallbackServerContext* context, const grpc::Status& status) {
    grpc::ServerUnaryReactor* reactor = context->DefaultReactor();
    reactor->Finish(status);
    return reactor;
}

/// A stream that ends at once with `status`.
template <class T>
class FailedStream : public grpc::ServerWriteReactor<T> {
  public:
    explicit FailedStream(const grpc::Status& status) { this->Finish(status); }
    void OnDone() override { delete this; }
};

grpc::Status unknownJob(const std::string& id) {
    return {grpc::StatusCode::NOT_FOUND, "no job '" + id + "'"};
}

pb::BudgetKind toProto(BudgetKind k) {
    switch (k) {
        case BudgetKind::SamplesPerPixel:
            return pb::BUDGET_KIND_SAMPLES_PER_PIXEL;
        case BudgetKind::MutationsPerPixel:
            return pb::BUDGET_KIND_MUTATIONS_PER_PIXEL;
        case BudgetKind::Seconds:
            return pb::BUDGET_KIND_SECONDS;
    }
    return pb::BUDGET_KIND_UNSPECIFIED;
}

}  // namespace

PartitaService::PartitaService(JobManager& jobs, const SceneSource& scenes,
                               const ServiceLimits& limits, const TokenAuth& auth,
                               Executor& executor)
    : jobs_(jobs), scenes_(scenes), limits_(limits), auth_(auth), executor_(executor) {}

grpc::ServerUnaryReactor* PartitaService::SubmitJob(grpc::CallbackServerContext* context,
                                                    const pb::SubmitJobRequest* request,
                                                    pb::SubmitJobResponse* response) {
    if (grpc::Status s = auth_.check(*context); !s.ok()) return finish(context, s);
    const pb::JobSpec& spec = request->spec();
    ValidatedSpec validated;
    if (grpc::Status s = validateJobSpec(spec, limits_, validated); !s.ok())
        return finish(context, s);
    if (spec.scene().has_scene_name()) {
        grpc::StatusCode code = grpc::StatusCode::OK;
        std::string error;
        if (scenes_.resolve(spec.scene().scene_name(), code, error).empty())
            return finish(context, {code, error});
    }
    pb::Job job;
    grpc::Status s = jobs_.submit(spec, job);
    if (s.ok()) {
        response->set_job_id(job.id());
        *response->mutable_job() = std::move(job);
    }
    return finish(context, s);
}

grpc::ServerWriteReactor<pb::JobEvent>* PartitaService::WatchJob(
    grpc::CallbackServerContext* context, const pb::WatchJobRequest* request) {
    if (grpc::Status s = auth_.check(*context); !s.ok()) return new FailedStream<pb::JobEvent>(s);
    std::shared_ptr<Job> job = jobs_.find(request->job_id());
    if (!job) return new FailedStream<pb::JobEvent>(unknownJob(request->job_id()));
    auto session = std::make_shared<WatchSession>(job->id(), request->raw_previews(), executor_);
    JobWatcher* key = session.get();
    auto* reactor = session->makeReactor([job, key] { job->removeWatcher(key); });
    if (grpc::Status s = job->addWatcher(session, request->previews(), limits_.maxWatchersPerJob);
        !s.ok())
        session->onClose(s);
    return reactor;
}

grpc::ServerUnaryReactor* PartitaService::GetJob(grpc::CallbackServerContext* context,
                                                 const pb::GetJobRequest* request,
                                                 pb::Job* response) {
    if (grpc::Status s = auth_.check(*context); !s.ok()) return finish(context, s);
    std::shared_ptr<Job> job = jobs_.find(request->job_id());
    if (!job) return finish(context, unknownJob(request->job_id()));
    *response = job->snapshot();
    return finish(context, grpc::Status::OK);
}

grpc::ServerUnaryReactor* PartitaService::ListJobs(grpc::CallbackServerContext* context,
                                                   const pb::ListJobsRequest* request,
                                                   pb::ListJobsResponse* response) {
    if (grpc::Status s = auth_.check(*context); !s.ok()) return finish(context, s);
    std::set<int> states;
    for (int state : request->states()) {
        if (!pb::JobState_IsValid(state) || state == pb::JOB_STATE_UNSPECIFIED)
            return finish(context, {grpc::StatusCode::INVALID_ARGUMENT,
                                    "unknown job state " + std::to_string(state)});
        states.insert(state);
    }
    for (auto& job : jobs_.list(request->label(), states)) *response->add_jobs() = std::move(job);
    return finish(context, grpc::Status::OK);
}

grpc::ServerUnaryReactor* PartitaService::CancelJob(grpc::CallbackServerContext* context,
                                                    const pb::CancelJobRequest* request,
                                                    pb::Job* response) {
    if (grpc::Status s = auth_.check(*context); !s.ok()) return finish(context, s);
    return finish(context, jobs_.cancel(request->job_id(), *response));
}

grpc::ServerUnaryReactor* PartitaService::DeleteJob(grpc::CallbackServerContext* context,
                                                    const pb::DeleteJobRequest* request,
                                                    pb::DeleteJobResponse*) {
    if (grpc::Status s = auth_.check(*context); !s.ok()) return finish(context, s);
    return finish(context, jobs_.remove(request->job_id()));
}

grpc::ServerWriteReactor<pb::ResultChunk>* PartitaService::FetchResult(
    grpc::CallbackServerContext* context, const pb::FetchResultRequest* request) {
    grpc::Status status = auth_.check(*context);
    std::filesystem::path file;
    if (status.ok()) {
        std::shared_ptr<Job> job = jobs_.find(request->job_id());
        const char* name = request->kind() == pb::RESULT_KIND_EXR        ? kResultExr
                           : request->kind() == pb::RESULT_KIND_PNG      ? kResultPng
                           : request->kind() == pb::RESULT_KIND_METADATA ? kResultMetadata
                                                                         : nullptr;
        if (!job) {
            status = unknownJob(request->job_id());
        } else if (!name) {
            status = {grpc::StatusCode::INVALID_ARGUMENT, "unknown result kind " +
                                                              std::to_string(int(request->kind())) +
                                                              ": ask for EXR, PNG or METADATA"};
        } else if (pb::JobState state = job->state(); state != pb::JOB_STATE_DONE) {
            status = {grpc::StatusCode::FAILED_PRECONDITION,
                      "job " + job->id() + " is " + stateName(state) +
                          ": results exist only once it is DONE"};
        } else {
            file = jobs_.resultDir(job->id()) / name;
        }
    }
    return makeResultStream(file, status);
}

grpc::ServerUnaryReactor* PartitaService::ListScenes(grpc::CallbackServerContext* context,
                                                     const pb::ListScenesRequest*,
                                                     pb::ListScenesResponse* response) {
    if (grpc::Status s = auth_.check(*context); !s.ok()) return finish(context, s);
    for (const auto& entry : scenes_.list()) {
        pb::SceneInfo* info = response->add_scenes();
        info->set_name(entry.name);
        info->set_file(entry.file);
    }
    return finish(context, grpc::Status::OK);
}

grpc::ServerUnaryReactor* PartitaService::GetServerInfo(grpc::CallbackServerContext* context,
                                                        const pb::ServerInfoRequest*,
                                                        pb::ServerInfo* response) {
    if (grpc::Status s = auth_.check(*context); !s.ok()) return finish(context, s);
    registerBuiltinAlgorithms();
    response->set_version(PARTITA_VERSION);
    response->set_threads(jobs_.threads());
    response->set_max_concurrent_jobs(jobs_.maxJobs());
    pb::Limits* l = response->mutable_limits();
    l->set_max_width(limits_.maxWidth);
    l->set_max_height(limits_.maxHeight);
    l->set_max_samples_per_pixel(limits_.maxSamplesPerPixel);
    l->set_max_seconds(limits_.maxSeconds);
    l->set_max_upload_bytes(limits_.maxUploadBytes);
    l->set_max_queued_jobs(limits_.maxQueuedJobs);
    l->set_max_watchers_per_job(limits_.maxWatchersPerJob);
    l->set_max_depth(limits_.maxDepth);
    const auto& registry = AlgorithmRegistry::instance();
    for (const auto& name : registry.names()) {
        const auto* entry = registry.find(name);
        pb::AlgorithmInfo* info = response->add_algorithms();
        info->set_name(entry->name);
        info->set_description(entry->description);
        info->set_native_budget(toProto(entry->nativeBudget));
    }
    return finish(context, grpc::Status::OK);
}

}  // namespace partita::server
