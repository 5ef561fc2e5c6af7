#include "result_stream.h"

#include <fstream>

#include "wire.h"

namespace partita::server {

namespace {

class ResultStream : public grpc::ServerWriteReactor<grpc::ByteBuffer> {
  public:
    ResultStream(const std::filesystem::path& file, const grpc::Status& status) {
        if (!status.ok()) {
            Finish(status);
            return;
        }
        in_.open(file, std::ios::binary);
        std::error_code ec;
        total_ = std::filesystem::file_size(file, ec);
        if (!in_ || ec) {
            Finish({grpc::StatusCode::INTERNAL,
                    "result file '" + file.filename().string() + "' cannot be read"});
            return;
        }
        next();
    }

    void OnWriteDone(bool ok) override {
        if (!ok) {
            Finish(grpc::Status::CANCELLED);
            return;
        }
        next();
    }
    void OnDone() override { delete this; }

  private:
    void next() {
        if (started_ && offset_ >= total_) {
            Finish(grpc::Status::OK);
            return;
        }
        std::string data(std::min<uint64_t>(kResultChunkBytes, total_ - offset_), '\0');
        if (!data.empty() && !in_.read(data.data(), std::streamsize(data.size()))) {
            Finish({grpc::StatusCode::INTERNAL, "result file could not be read"});
            return;
        }
        chunk_.set_offset(offset_);
        chunk_.set_total_size(total_);
        chunk_.set_data(std::move(data));
        offset_ += chunk_.data().size();
        started_ = true;  // an empty file still gets one (empty) chunk
        wire_ = serialize(chunk_);
        chunk_.Clear();
        StartWrite(&wire_);
    }

    std::ifstream in_;
    uint64_t total_ = 0, offset_ = 0;
    bool started_ = false;
    pb::ResultChunk chunk_;
    grpc::ByteBuffer wire_;
};

}  // namespace

grpc::ServerWriteReactor<grpc::ByteBuffer>* makeResultStream(const std::filesystem::path& file,
                                                             const grpc::Status& status) {
    return new ResultStream(file, status);
}

}  // namespace partita::server
