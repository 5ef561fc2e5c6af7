#include "partita_service.h"

#include <spdlog/spdlog.h>

#include "result_stream.h"
#include "text.h"
#include "upload_session.h"
#include "watch_session.h"
#include "wire.h"

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

}  // namespace

PartitaService::PartitaService(JobManager& jobs, const SceneSource& scenes,
                               const ServiceLimits& limits, const TokenAuth& auth,
                               Executor& executor, UploadStaging& uploads)
    : api_(jobs, scenes, limits, &uploads), limits_(limits), auth_(auth), executor_(executor) {}

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

grpc::ServerReadReactor<grpc::ByteBuffer>* PartitaService::UploadScene(Context* c, Bytes* out) {
    return new UploadSession(
        c, api_, out, [this, c](const grpc::Status& s) { return outcome(c, "UploadScene", s); },
        auth_.check(*c));
}

grpc::ServerUnaryReactor* PartitaService::SubmitJob(Context* c, const Bytes* in, Bytes* out) {
    return unary<pb::SubmitJobRequest, pb::SubmitJobResponse>(
        c, "SubmitJob", *in, *out, [this](const auto& rq, auto& rs) {
            grpc::Status s = api_.submit(rq.spec(), *rs.mutable_job());
            if (s.ok()) rs.set_job_id(rs.job().id());
            return s;
        });
}

grpc::ServerUnaryReactor* PartitaService::GetJob(Context* c, const Bytes* in, Bytes* out) {
    return unary<pb::GetJobRequest, pb::Job>(
        c, "GetJob", *in, *out,
        [this](const auto& rq, auto& rs) { return api_.get(rq.job_id(), rs); });
}

grpc::ServerUnaryReactor* PartitaService::ListJobs(Context* c, const Bytes* in, Bytes* out) {
    return unary<pb::ListJobsRequest, pb::ListJobsResponse>(
        c, "ListJobs", *in, *out, [this](const auto& rq, auto& rs) { return api_.list(rq, rs); });
}

grpc::ServerUnaryReactor* PartitaService::CancelJob(Context* c, const Bytes* in, Bytes* out) {
    return unary<pb::CancelJobRequest, pb::Job>(
        c, "CancelJob", *in, *out,
        [this](const auto& rq, auto& rs) { return api_.cancel(rq.job_id(), rs); });
}

grpc::ServerUnaryReactor* PartitaService::DeleteJob(Context* c, const Bytes* in, Bytes* out) {
    return unary<pb::DeleteJobRequest, pb::DeleteJobResponse>(
        c, "DeleteJob", *in, *out,
        [this](const auto& rq, auto&) { return api_.remove(rq.job_id()); });
}

grpc::ServerUnaryReactor* PartitaService::ListScenes(Context* c, const Bytes* in, Bytes* out) {
    return unary<pb::ListScenesRequest, pb::ListScenesResponse>(c, "ListScenes", *in, *out,
                                                                [this](const auto&, auto& rs) {
                                                                    api_.listScenes(rs);
                                                                    return grpc::Status::OK;
                                                                });
}

grpc::ServerUnaryReactor* PartitaService::GetServerInfo(Context* c, const Bytes* in, Bytes* out) {
    return unary<pb::ServerInfoRequest, pb::ServerInfo>(c, "GetServerInfo", *in, *out,
                                                        [this](const auto&, auto& rs) {
                                                            api_.serverInfo(rs);
                                                            return grpc::Status::OK;
                                                        });
}

grpc::ServerWriteReactor<grpc::ByteBuffer>* PartitaService::WatchJob(Context* c, const Bytes* in) {
    pb::WatchJobRequest request;
    grpc::Status status = auth_.check(*c);
    if (status.ok()) status = parseRequest(*in, request);
    std::shared_ptr<Job> job;
    if (status.ok() && !(job = api_.find(request.job_id()))) status = unknownJob(request.job_id());
    if (status.ok() && request.raw_previews()) status = api_.checkRawPreviews(*job);
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
    if (status.ok()) status = api_.resultFile(request.job_id(), request.kind(), file);
    return makeResultStream(file, outcome(c, "FetchResult", status));
}

}  // namespace partita::server
