#include "job_event_stream.h"

#include "http_wire.h"

namespace partita::server::dashboard {

void JobEventStream::onState(const pb::Job& job) {
    std::lock_guard lock(mutex_);
    Item item{Item::State, job, {}, nullptr};
    item.job.mutable_progress()->clear_partitions();  // the progress events carry them
    queue_.push_back(std::move(item));
    if (isTerminal(job.state())) terminalQueued_ = true;
    ready_.notify_one();
}

JobEventStream::Item* JobEventStream::pendingAfterLastState(Item::Kind kind) {
    for (auto it = queue_.rbegin(); it != queue_.rend(); ++it) {
        if (it->kind == Item::State) return nullptr;
        if (it->kind == kind) return &*it;
    }
    return nullptr;
}

void JobEventStream::onProgress(const pb::Progress& progress) {
    std::lock_guard lock(mutex_);
    if (Item* waiting = pendingAfterLastState(Item::Progress))
        waiting->progress = progress;
    else
        queue_.push_back(Item{Item::Progress, {}, progress, nullptr});
    ready_.notify_one();
}

void JobEventStream::onFrame(std::shared_ptr<const PreviewFrameData> frame) {
    std::lock_guard lock(mutex_);
    if (Item* waiting = pendingAfterLastState(Item::Frame))
        waiting->frame = std::move(frame);
    else
        queue_.push_back(Item{Item::Frame, {}, {}, std::move(frame)});
    ready_.notify_one();
}

void JobEventStream::onClose(const grpc::Status& status) {
    std::lock_guard lock(mutex_);
    closed_ = true;
    closeStatus_ = status;
    ready_.notify_one();
}

JobEventStream::Event JobEventStream::render(Item& item) {
    switch (item.kind) {
        case Item::State:
            return {"state", toJson(item.job)};
        case Item::Progress:
            return {"progress", toJson(item.progress)};
        case Item::Frame: {
            pb::PreviewFrame frame = item.frame->encode(false);
            return {"frame", toJson(frame)};
        }
    }
    return {};
}

JobEventStream::Next JobEventStream::next(std::chrono::milliseconds timeout, Event& out) {
    std::unique_lock lock(mutex_);
    auto hasWork = [&] { return !queue_.empty() || closed_ || terminalQueued_; };
    if (!ready_.wait_for(lock, timeout, hasWork)) return Next::Timeout;
    if (!queue_.empty()) {
        Item item = std::move(queue_.front());
        queue_.pop_front();
        lock.unlock();  // encoding a frame takes a while: never under the lock the job takes
        try {
            out = render(item);
        } catch (const std::exception& e) {  // a finished job's frame that cannot be read back
            out = {"end", errorJson({grpc::StatusCode::INTERNAL, e.what()})};
        }
        return Next::Event;
    }
    if (closed_ && !closeSent_ && !terminalQueued_) {
        closeSent_ = true;
        out = {"end", errorJson(closeStatus_)};
        return Next::Event;
    }
    return Next::End;
}

}  // namespace partita::server::dashboard
