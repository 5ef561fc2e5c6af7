// The gRPC face of the daemon (partita.v1.Partita, callback API): checks the token, maps requests
// to the job manager and scene source, and maps their answers and errors to messages and status
// codes. No job logic lives here.
//
// Every method is registered raw (ByteBuffer in and out): requests are parsed by wire.h, so a
// malformed one gets INVALID_ARGUMENT naming the bad field (gRPC would answer UNIMPLEMENTED), and
// every response has valid UTF-8 in its strings. Refusals are logged (reject_log.h) and status
// messages are bounded in length.
#pragma once

#include <atomic>

#include "auth.h"
#include "executor.h"
#include "job_api.h"
#include "proto.h"
#include "reject_log.h"
#include "scene_source.h"
#include "service_limits.h"

namespace partita::server {

// Every method of the service in its raw (ByteBuffer) form.
using RawPartitaService = pb::Partita::WithRawCallbackMethod_UploadScene<
    pb::Partita::WithRawCallbackMethod_SubmitJob<pb::Partita::WithRawCallbackMethod_WatchJob<
        pb::Partita::WithRawCallbackMethod_GetJob<pb::Partita::WithRawCallbackMethod_ListJobs<
            pb::Partita::WithRawCallbackMethod_CancelJob<
                pb::Partita::WithRawCallbackMethod_DeleteJob<
                    pb::Partita::WithRawCallbackMethod_FetchResult<
                        pb::Partita::WithRawCallbackMethod_ListScenes<
                            pb::Partita::WithRawCallbackMethod_GetServerInfo<
                                pb::Partita::Service>>>>>>>>>>;

class PartitaService final : public RawPartitaService {
  public:
    using Context = grpc::CallbackServerContext;
    using Bytes = grpc::ByteBuffer;

    PartitaService(JobManager& jobs, const SceneSource& scenes, const ServiceLimits& limits,
                   const TokenAuth& auth, Executor& executor, UploadStaging& uploads);

    grpc::ServerReadReactor<Bytes>* UploadScene(Context* c, Bytes* out) override;
    grpc::ServerUnaryReactor* SubmitJob(Context* c, const Bytes* in, Bytes* out) override;
    grpc::ServerWriteReactor<Bytes>* WatchJob(Context* c, const Bytes* in) override;
    grpc::ServerUnaryReactor* GetJob(Context* c, const Bytes* in, Bytes* out) override;
    grpc::ServerUnaryReactor* ListJobs(Context* c, const Bytes* in, Bytes* out) override;
    grpc::ServerUnaryReactor* CancelJob(Context* c, const Bytes* in, Bytes* out) override;
    grpc::ServerUnaryReactor* DeleteJob(Context* c, const Bytes* in, Bytes* out) override;
    grpc::ServerWriteReactor<Bytes>* FetchResult(Context* c, const Bytes* in) override;
    grpc::ServerUnaryReactor* ListScenes(Context* c, const Bytes* in, Bytes* out) override;
    grpc::ServerUnaryReactor* GetServerInfo(Context* c, const Bytes* in, Bytes* out) override;

  private:
    /// Token check, parse, `handler(request, response)`, serialize, finish.
    template <class Req, class Resp, class Handler>
    grpc::ServerUnaryReactor* unary(Context* c, const char* method, const Bytes& in, Bytes& out,
                                    Handler handler);
    /// The status as sent (message bounded), logged when it is a refusal.
    grpc::Status outcome(Context* c, const char* method, const grpc::Status& status);

    JobApi api_;
    const ServiceLimits& limits_;
    const TokenAuth& auth_;
    Executor& executor_;
    RejectLog rejects_;
    std::atomic<int> openWatches_{0};  // WatchJob streams of all jobs, against maxWatchStreams
};

}  // namespace partita::server
