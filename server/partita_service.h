// The gRPC face of the daemon (partita.v1.Partita, callback API): checks the token, maps requests
// to the job manager and scene source, and maps their answers and errors to messages and status
// codes. No job logic lives here.
#pragma once

#include "auth.h"
#include "executor.h"
#include "job_manager.h"
#include "proto.h"
#include "scene_source.h"
#include "service_limits.h"

namespace partita::server {

class PartitaService final : public pb::Partita::CallbackService {
  public:
    PartitaService(JobManager& jobs, const SceneSource& scenes, const ServiceLimits& limits,
                   const TokenAuth& auth, Executor& executor);

    grpc::ServerUnaryReactor* SubmitJob(grpc::CallbackServerContext* context,
                                        const pb::SubmitJobRequest* request,
                                        pb::SubmitJobResponse* response) override;
    grpc::ServerWriteReactor<pb::JobEvent>* WatchJob(grpc::CallbackServerContext* context,
                                                     const pb::WatchJobRequest* request) override;
    grpc::ServerUnaryReactor* GetJob(grpc::CallbackServerContext* context,
                                     const pb::GetJobRequest* request, pb::Job* response) override;
    grpc::ServerUnaryReactor* ListJobs(grpc::CallbackServerContext* context,
                                       const pb::ListJobsRequest* request,
                                       pb::ListJobsResponse* response) override;
    grpc::ServerUnaryReactor* CancelJob(grpc::CallbackServerContext* context,
                                        const pb::CancelJobRequest* request,
                                        pb::Job* response) override;
    grpc::ServerUnaryReactor* DeleteJob(grpc::CallbackServerContext* context,
                                        const pb::DeleteJobRequest* request,
                                        pb::DeleteJobResponse* response) override;
    grpc::ServerWriteReactor<pb::ResultChunk>* FetchResult(
        grpc::CallbackServerContext* context, const pb::FetchResultRequest* request) override;
    grpc::ServerUnaryReactor* ListScenes(grpc::CallbackServerContext* context,
                                         const pb::ListScenesRequest* request,
                                         pb::ListScenesResponse* response) override;
    grpc::ServerUnaryReactor* GetServerInfo(grpc::CallbackServerContext* context,
                                            const pb::ServerInfoRequest* request,
                                            pb::ServerInfo* response) override;

  private:
    JobManager& jobs_;
    const SceneSource& scenes_;
    const ServiceLimits& limits_;
    const TokenAuth& auth_;
    Executor& executor_;
};

}  // namespace partita::server
