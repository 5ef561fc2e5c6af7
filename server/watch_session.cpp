#include "watch_session.h"

#include <algorithm>

#include <spdlog/spdlog.h>

#include "wire.h"

namespace partita::server {

class WatchSession::StreamReactor : public Reactor {
  public:
    StreamReactor(std::shared_ptr<WatchSession> session, std::function<void()> onDone)
        : session_(std::move(session)), onDone_(std::move(onDone)) {}
    void OnWriteDone(bool ok) override { session_->writeDone(ok); }
    void OnCancel() override { session_->cancelled(); }
    void OnDone() override {
        session_->done();
        if (onDone_) onDone_();
        delete this;
    }

  private:
    std::shared_ptr<WatchSession> session_;
    std::function<void()> onDone_;
};

WatchSession::WatchSession(std::string jobId, bool raw, Executor& executor)
    : jobId_(std::move(jobId)), raw_(raw), executor_(executor) {}

WatchSession::Reactor* WatchSession::makeReactor(std::function<void()> onDone) {
    auto* reactor = new StreamReactor(shared_from_this(), std::move(onDone));
    std::lock_guard lock(mutex_);
    reactor_ = reactor;
    return reactor;
}

void WatchSession::onState(const pb::Job& job) {
    Pending p{Pending::State, {}, nullptr, isTerminal(job.state())};
    p.event.set_job_id(jobId_);
    *p.event.mutable_state() = job;
    enqueue(std::move(p));
}

void WatchSession::onProgress(const pb::Progress& progress) {
    Pending p{Pending::Progress, {}, nullptr, false};
    p.event.set_job_id(jobId_);
    *p.event.mutable_progress() = progress;
    enqueue(std::move(p));
}

void WatchSession::onFrame(std::shared_ptr<const PreviewFrameData> frame) {
    enqueue(Pending{Pending::Frame, {}, std::move(frame), false});
}

void WatchSession::onClose(const grpc::Status& status) {
    std::lock_guard lock(mutex_);
    if (finished_) return;
    closeStatus_ = status;
    scheduleLocked();
}

void WatchSession::enqueue(Pending item) {
    std::lock_guard lock(mutex_);
    if (finished_ || cancelled_ || closeStatus_) return;
    // Keep at most one pending progress report of a phase after the last pending state and one
    // pending intermediate frame: the newest. A progress report before a state, or of another
    // phase, stays: it is the last of its phase (several phases may share a state: the
    // pre-pass and the pilots).
    if (item.kind == Pending::Progress) {
        auto lastState = std::find_if(queue_.rbegin(), queue_.rend(),
                                      [](const Pending& p) { return p.kind == Pending::State; });
        const std::string& phase = item.event.progress().phase();
        queue_.erase(std::remove_if(lastState.base(), queue_.end(),
                                    [&](const Pending& p) {
                                        return p.kind == Pending::Progress &&
                                               p.event.progress().phase() == phase;
                                    }),
                     queue_.end());
    } else if (item.kind == Pending::Frame) {
        std::erase_if(queue_, [](const Pending& p) {
            return p.kind == Pending::Frame && !p.frame->isFinal();
        });
    }
    queue_.push_back(std::move(item));
    scheduleLocked();
}

void WatchSession::scheduleLocked() {
    if (busy_ || finished_) return;
    busy_ = true;
    executor_.post([self = shared_from_this()] { self->pump(); });
}

void WatchSession::pump() {
    std::unique_lock lock(mutex_);
    if (finished_ || !reactor_) {
        busy_ = false;
        return;
    }
    std::optional<grpc::Status> finishWith;
    if (cancelled_) {
        finishWith = grpc::Status::CANCELLED;
    } else if (queue_.empty()) {
        if (terminalSent_)
            finishWith = grpc::Status::OK;
        else if (closeStatus_)
            finishWith = *closeStatus_;
    }
    if (finishWith) {
        finished_ = true;
        Reactor* reactor = reactor_;
        lock.unlock();
        reactor->Finish(*finishWith);  // OnDone may run (and delete the reactor) from here on
        return;
    }
    if (queue_.empty()) {
        busy_ = false;
        return;
    }
    Pending item = std::move(queue_.front());
    queue_.pop_front();
    Reactor* reactor = reactor_;
    lock.unlock();

    // Holding the busy token: nobody else writes, finishes or lets OnDone run meanwhile.
    current_.Clear();
    currentFrame_.reset();
    const grpc::ByteBuffer* message = &current_;
    if (item.kind == Pending::Frame) {
        try {
            currentFrame_ = item.frame->wireEvent(jobId_, raw_);
            message = currentFrame_.get();
        } catch (const std::exception& e) {
            spdlog::warn("[job {}] preview frame {} not sent: {}", jobId_, item.frame->sequence(),
                         e.what());
            lock.lock();
            busy_ = false;
            scheduleLocked();
            return;
        }
    } else {
        current_ = serialize(item.event);
    }
    if (item.terminal) {
        lock.lock();
        terminalSent_ = true;
        lock.unlock();
    }
    reactor->StartWrite(message);
}

void WatchSession::writeDone(bool ok) {
    std::lock_guard lock(mutex_);
    currentFrame_.reset();  // let the frame's buffer go once every watcher has sent it
    if (!ok) cancelled_ = true;
    // Still busy: the next pump continues (or finishes) the stream.
    executor_.post([self = shared_from_this()] { self->pump(); });
}

void WatchSession::cancelled() {
    std::unique_lock lock(mutex_);
    cancelled_ = true;
    queue_.clear();
    if (busy_ || finished_) return;  // the busy holder finishes the stream
    busy_ = true;
    executor_.post([self = shared_from_this()] { self->pump(); });
}

void WatchSession::done() {
    std::lock_guard lock(mutex_);
    reactor_ = nullptr;
    finished_ = true;
    queue_.clear();
}

}  // namespace partita::server
