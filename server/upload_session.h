// The server side of one UploadScene stream: reads UploadChunks one at a time and hands their
// bytes to an UploadWriter (upload_staging.h), so the daemon holds one message of an upload,
// never the scene. The first message must carry the header (admission happens there); the
// stream's end finishes the upload and answers its id.
#pragma once

#include <grpcpp/grpcpp.h>

#include <functional>
#include <memory>

#include "job_api.h"
#include "upload_staging.h"

namespace partita::server {

class UploadSession final : public grpc::ServerReadReactor<grpc::ByteBuffer> {
  public:
    /// `outcome` maps a status to the one sent (and logs refusals). `start` is the status of
    /// the checks before the first read (the token): not OK ends the stream at once.
    UploadSession(grpc::CallbackServerContext* context, JobApi& api, grpc::ByteBuffer* response,
                  std::function<grpc::Status(const grpc::Status&)> outcome,
                  const grpc::Status& start);

    void OnReadDone(bool ok) override;
    void OnDone() override { delete this; }

  private:
    /// The stream ended from the client's side: finish the upload.
    void complete();
    void end(const grpc::Status& status) { Finish(outcome_(status)); }

    grpc::CallbackServerContext* context_;
    JobApi& api_;
    grpc::ByteBuffer* response_;
    std::function<grpc::Status(const grpc::Status&)> outcome_;
    grpc::ByteBuffer message_;
    std::unique_ptr<UploadWriter> writer_;  // after the header
};

}  // namespace partita::server
