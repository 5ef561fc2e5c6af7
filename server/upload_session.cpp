#include "upload_session.h"

#include "wire.h"

namespace partita::server {

UploadSession::UploadSession(grpc::CallbackServerContext* context, JobApi& api,
                             grpc::ByteBuffer* response,
                             std::function<grpc::Status(const grpc::Status&)> outcome,
                             const grpc::Status& start)
    : context_(context), api_(api), response_(response), outcome_(std::move(outcome)) {
    if (!start.ok()) {
        end(start);
        return;
    }
    StartRead(&message_);
}

void UploadSession::OnReadDone(bool ok) {
    if (!ok) {
        complete();
        return;
    }
    pb::UploadChunk chunk;
    grpc::Status status = parseRequest(message_, chunk);
    message_.Clear();
    if (status.ok() && !writer_) {
        if (!chunk.has_header())
            status = {grpc::StatusCode::INVALID_ARGUMENT,
                      "an upload's first message must carry its header"};
        else
            status = api_.beginUpload(chunk.header(), writer_);
    } else if (status.ok() && chunk.has_header()) {
        status = {grpc::StatusCode::INVALID_ARGUMENT,
                  "an upload carries its header in the first message only"};
    }
    if (status.ok()) status = writer_->append(chunk.data());
    if (!status.ok()) {
        writer_.reset();  // removes what was written and frees the admission now
        end(status);
        return;
    }
    StartRead(&message_);
}

void UploadSession::complete() {
    if (context_->IsCancelled()) {
        writer_.reset();
        end({grpc::StatusCode::CANCELLED, "the upload was cancelled"});
        return;
    }
    if (!writer_) {
        end({grpc::StatusCode::INVALID_ARGUMENT, "the upload sent no header"});
        return;
    }
    pb::UploadSceneResponse response;
    grpc::Status status = writer_->finish(response);
    writer_.reset();
    if (status.ok()) *response_ = serialize(response);
    end(status);
}

}  // namespace partita::server
