// PreviewFrameData::wireEvent: kept apart from preview_frame.cpp, which deals in images.
#include "preview_frame.h"
#include "wire.h"

namespace partita::server {

std::shared_ptr<const grpc::ByteBuffer> PreviewFrameData::wireEvent(const std::string& jobId,
                                                                    bool raw) const {
    {
        std::lock_guard lock(mutex_);
        if (auto shared = wire_[raw].lock()) return shared;
    }
    // Serialized outside the lock: two watchers racing at most serialize twice, never block.
    pb::JobEvent event;
    event.set_job_id(jobId);
    *event.mutable_preview() = encode(raw);
    auto shared = std::make_shared<const grpc::ByteBuffer>(serialize(event));
    std::lock_guard lock(mutex_);
    if (auto other = wire_[raw].lock()) return other;
    wire_[raw] = shared;
    return shared;
}

}  // namespace partita::server
