#include "partita_service.h"

#include <spdlog/spdlog.h>

#include "algorithm.h"
#include "job_runner.h"
#include "parameter_wire.h"
#include "result_stream.h"
#include "text.h"
#include "validation.h"
#include "watch_session.h"
#include "wire.h"

#ifndef PARTITA_VERSION
#define PARTITA_VERSION "0.0.0"
#endif

namespace partita::server {

namespace {

// Status messages travel in a header; clients limit headers (8 KiB is common). Messages quote
// input only in short prefixes (text.h), so this is a last guard, not the usual case.
constexpr size_t kMaxStatusMessage = 1024;

/// A stream that ends at once with `status`.
class FailedStream : public grpc::ServerWriteReactor<grpc::ByteBuffer> {
  public:
    explicit FailedStream(const grpc::Status& status) { Finish(status); }
    void OnDone() override { delete this; }
};

grpc::Status unknownJob(const std::string& id) {
    return {grpc::StatusCode::NOT_FOUND, "no job '" + quoteInput(id) + "'"};
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

grpc::Status PartitaService::outcome(Context* c, const char* method, const grpc::Status& status) {
    if (status.ok()) return status;
    grpc::Status sent = status;
    std::string message = status.error_message();
    if (message.size() > kMaxStatusMessage || !isValidUtf8(message))
        sent = grpc::Status(status.error_code(), quoteInput(message, kMaxStatusMessage));
    rejects_.note(method, c->peer(), sent);
    return sent;
}

template <class Req, class Resp, class Handler>
grpc::ServerUnaryReactor* PartitaService::unary(Context* c, const char* method, const Bytes& in,
                                                Bytes& out, Handler handler) {
    Req request;
    Resp response;
    grpc::Status status = auth_.check(*c);
    if (status.ok()) status = parseRequest(in, request);
    if (status.ok()) {
        try {
            status = handler(request, response);
            if (status.ok()) out = serialize(response);
        } catch (const std::exception& e) {
            spdlog::error("{} failed: {}", method, e.what());
            status = {grpc::StatusCode::INTERNAL, std::string(method) + " failed: " + e.what()};
        }
    }
    grpc::ServerUnaryReactor* reactor = c->DefaultReactor();
    reactor->Finish(outcome(c, method, status));
    return reactor;
}

grpc::ServerUnaryReactor* PartitaService::SubmitJob(Context* c, const Bytes* in, Bytes* out) {
    return unary<pb::SubmitJobRequest, pb::SubmitJobResponse>(
        c, "SubmitJob", *in, *out, [this](const auto& rq, auto& rs) { return submitJob(rq, rs); });
}

grpc::ServerUnaryReactor* PartitaService::GetJob(Context* c, const Bytes* in, Bytes* out) {
    return unary<pb::GetJobRequest, pb::Job>(
        c, "GetJob", *in, *out, [this](const auto& rq, auto& rs) { return getJob(rq, rs); });
}

grpc::ServerUnaryReactor* PartitaService::ListJobs(Context* c, const Bytes* in, Bytes* out) {
    return unary<pb::ListJobsRequest, pb::ListJobsResponse>(
        c, "ListJobs", *in, *out, [this](const auto& rq, auto& rs) { return listJobs(rq, rs); });
}

grpc::ServerUnaryReactor* PartitaService::CancelJob(Context* c, const Bytes* in, Bytes* out) {
    return unary<pb::CancelJobRequest, pb::Job>(
        c, "CancelJob", *in, *out,
        [this](const auto& rq, auto& rs) { return jobs_.cancel(rq.job_id(), rs); });
}

grpc::ServerUnaryReactor* PartitaService::DeleteJob(Context* c, const Bytes* in, Bytes* out) {
    return unary<pb::DeleteJobRequest, pb::DeleteJobResponse>(
        c, "DeleteJob", *in, *out,
        [this](const auto& rq, auto&) { return jobs_.remove(rq.job_id()); });
}

grpc::ServerUnaryReactor* PartitaService::ListScenes(Context* c, const Bytes* in, Bytes* out) {
    return unary<pb::ListScenesRequest, pb::ListScenesResponse>(
        c, "ListScenes", *in, *out, [this](const auto&, auto& rs) { return listScenes(rs); });
}

grpc::ServerUnaryReactor* PartitaService::GetServerInfo(Context* c, const Bytes* in, Bytes* out) {
    return unary<pb::ServerInfoRequest, pb::ServerInfo>(
        c, "GetServerInfo", *in, *out, [this](const auto&, auto& rs) { return serverInfo(rs); });
}

grpc::ServerWriteReactor<grpc::ByteBuffer>* PartitaService::WatchJob(Context* c, const Bytes* in) {
    pb::WatchJobRequest request;
    grpc::Status status = auth_.check(*c);
    if (status.ok()) status = parseRequest(*in, request);
    std::shared_ptr<Job> job;
    if (status.ok() && !(job = jobs_.find(request.job_id()))) status = unknownJob(request.job_id());
    if (status.ok() && openWatches_.fetch_add(1) >= limits_.maxWatchStreams) {
        openWatches_.fetch_sub(1);
        status = {grpc::StatusCode::RESOURCE_EXHAUSTED,
                  "this server already has " + std::to_string(limits_.maxWatchStreams) +
                      " open watch streams, its limit (--max-watch-streams)"};
    }
    if (!status.ok()) return new FailedStream(outcome(c, "WatchJob", status));
    auto session = std::make_shared<WatchSession>(job->id(), request.raw_previews(), executor_);
    JobWatcher* key = session.get();
    auto* reactor = session->makeReactor([this, job, key] {
        job->removeWatcher(key);
        openWatches_.fetch_sub(1);
    });
    if (grpc::Status s = job->addWatcher(session, request.previews(), limits_.maxWatchersPerJob);
        !s.ok())
        session->onClose(outcome(c, "WatchJob", s));
    return reactor;
}

grpc::ServerWriteReactor<grpc::ByteBuffer>* PartitaService::FetchResult(Context* c,
                                                                        const Bytes* in) {
    pb::FetchResultRequest request;
    std::filesystem::path file;
    grpc::Status status = auth_.check(*c);
    if (status.ok()) status = parseRequest(*in, request);
    if (status.ok()) status = resultFile(request, file);
    return makeResultStream(file, outcome(c, "FetchResult", status));
}

grpc::Status PartitaService::submitJob(const pb::SubmitJobRequest& request,
                                       pb::SubmitJobResponse& response) {
    const pb::JobSpec& spec = request.spec();
    ValidatedSpec validated;
    if (grpc::Status s = validateJobSpec(spec, limits_, validated); !s.ok()) return s;
    if (spec.scene().has_scene_name()) {
        grpc::StatusCode code = grpc::StatusCode::OK;
        std::string error;
        if (scenes_.resolve(spec.scene().scene_name(), code, error).empty()) return {code, error};
    }
    if (grpc::Status s = checkEnvironmentImage(spec, scenes_, limits_, validated); !s.ok())
        return s;
    pb::Job job;
    grpc::Status s = jobs_.submit(spec, validated, job);
    if (s.ok()) {
        response.set_job_id(job.id());
        *response.mutable_job() = std::move(job);
    }
    return s;
}

grpc::Status PartitaService::getJob(const pb::GetJobRequest& request, pb::Job& response) {
    std::shared_ptr<Job> job = jobs_.find(request.job_id());
    if (!job) return unknownJob(request.job_id());
    response = job->snapshot();
    return grpc::Status::OK;
}

grpc::Status PartitaService::listJobs(const pb::ListJobsRequest& request,
                                      pb::ListJobsResponse& response) {
    std::set<int> states;
    for (int state : request.states()) {
        if (!pb::JobState_IsValid(state) || state == pb::JOB_STATE_UNSPECIFIED)
            return {grpc::StatusCode::INVALID_ARGUMENT,
                    "unknown job state " + std::to_string(state)};
        states.insert(state);
    }
    for (auto& job : jobs_.list(request.label(), states)) *response.add_jobs() = std::move(job);
    return grpc::Status::OK;
}

grpc::Status PartitaService::resultFile(const pb::FetchResultRequest& request,
                                        std::filesystem::path& file) {
    std::shared_ptr<Job> job = jobs_.find(request.job_id());
    const char* name = request.kind() == pb::RESULT_KIND_EXR        ? kResultExr
                       : request.kind() == pb::RESULT_KIND_PNG      ? kResultPng
                       : request.kind() == pb::RESULT_KIND_METADATA ? kResultMetadata
                                                                    : nullptr;
    if (!job) return unknownJob(request.job_id());
    if (!name)
        return {grpc::StatusCode::INVALID_ARGUMENT, "unknown result kind " +
                                                        std::to_string(int(request.kind())) +
                                                        ": ask for EXR, PNG or METADATA"};
    if (pb::JobState state = job->state(); state != pb::JOB_STATE_DONE)
        return {grpc::StatusCode::FAILED_PRECONDITION, "job " + job->id() + " is " +
                                                           stateName(state) +
                                                           ": results exist only once it is DONE"};
    file = jobs_.resultDir(job->id()) / name;
    return grpc::Status::OK;
}

grpc::Status PartitaService::listScenes(pb::ListScenesResponse& response) {
    for (const auto& entry : scenes_.list()) {
        pb::SceneInfo* info = response.add_scenes();
        info->set_name(entry.name);
        info->set_file(entry.file);
    }
    return grpc::Status::OK;
}

grpc::Status PartitaService::serverInfo(pb::ServerInfo& response) {
    registerBuiltinAlgorithms();
    response.set_version(PARTITA_VERSION);
    response.set_threads(jobs_.threads());
    response.set_max_concurrent_jobs(jobs_.maxJobs());
    pb::Limits* l = response.mutable_limits();
    l->set_max_width(limits_.maxWidth);
    l->set_max_height(limits_.maxHeight);
    l->set_max_samples_per_pixel(limits_.maxSamplesPerPixel);
    l->set_max_seconds(limits_.maxSeconds);
    l->set_max_upload_bytes(limits_.maxUploadBytes);
    l->set_max_queued_jobs(limits_.maxQueuedJobs);
    l->set_max_watchers_per_job(limits_.maxWatchersPerJob);
    l->set_max_depth(limits_.maxDepth);
    l->set_max_job_memory_bytes(limits_.maxJobMemoryBytes);
    l->set_max_store_bytes(limits_.maxStoreBytes);
    l->set_max_bootstrap_samples(limits_.maxBootstrapSamples);
    const auto& registry = AlgorithmRegistry::instance();
    for (const auto& name : registry.names()) {
        const auto* entry = registry.find(name);
        pb::AlgorithmInfo* info = response.add_algorithms();
        info->set_name(entry->name);
        info->set_description(entry->description);
        info->set_native_budget(toProto(entry->nativeBudget));
        describeAlgorithmParameters(*entry, *info);
    }
    return grpc::Status::OK;
}

}  // namespace partita::server
