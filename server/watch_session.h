// One WatchJob stream: a JobWatcher that queues the job's events and a gRPC write reactor that
// sends them, one write at a time.
//
// The queue holds every state change in order, but at most one progress report per phase
// between two state changes and one intermediate preview frame (a newer one replaces the pending
// one), so a slow client skips frames and never holds back the render or other watchers. The
// final frame is never dropped, nor the last progress of a phase (the one queued before the next
// state or the next phase's).
// The stream ends with OK after the terminal state has been sent.
//
// Memory: a stalled watcher holds at most one message in flight and one pending frame, and a
// frame's serialized bytes are shared by all watchers sending it (PreviewFrameData::wireEvent).
//
// Lifetime: the session is shared (job, executor tasks, reactor); the reactor is deleted by gRPC
// in OnDone, after which the session never touches it. StartWrite and Finish are only called by
// whoever holds the session's single "busy" token, and never under the session's lock.
#pragma once

#include <grpcpp/grpcpp.h>

#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>

#include "executor.h"
#include "job.h"

namespace partita::server {

class WatchSession : public JobWatcher, public std::enable_shared_from_this<WatchSession> {
  public:
    using Reactor = grpc::ServerWriteReactor<grpc::ByteBuffer>;  // serialized JobEvents

    WatchSession(std::string jobId, bool raw, Executor& executor);

    /// Creates the reactor gRPC drives; `onDone` runs when the stream is over (unsubscribe).
    Reactor* makeReactor(std::function<void()> onDone);

    void onState(const pb::Job& job) override;
    void onProgress(const pb::Progress& progress) override;
    void onFrame(std::shared_ptr<const PreviewFrameData> frame) override;
    void onClose(const grpc::Status& status) override;

  private:
    class StreamReactor;
    struct Pending {
        enum Kind { State, Progress, Frame } kind;
        pb::JobEvent event;                             // State, Progress
        std::shared_ptr<const PreviewFrameData> frame;  // Frame
        bool terminal = false;                          // a terminal state
    };

    void enqueue(Pending item);  // takes the lock
    void scheduleLocked();       // with the lock held
    void pump();                 // on the executor: send the next item or finish
    void writeDone(bool ok);     // reactor: OnWriteDone
    void cancelled();            // reactor: OnCancel
    void done();                 // reactor: OnDone

    const std::string jobId_;
    const bool raw_;
    Executor& executor_;

    std::mutex mutex_;
    Reactor* reactor_ = nullptr;  // null after OnDone
    std::deque<Pending> queue_;
    bool busy_ = false;       // a pump is scheduled or a write is in flight
    bool finished_ = false;   // Finish was called (or the stream is done)
    bool cancelled_ = false;  // the client went away
    bool terminalSent_ = false;
    std::optional<grpc::Status> closeStatus_;
    // The message being written (owned by the busy holder): a state or progress event of its
    // own, or a preview frame's buffer shared with the other watchers sending it.
    grpc::ByteBuffer current_;
    std::shared_ptr<const grpc::ByteBuffer> currentFrame_;
};

}  // namespace partita::server
