// One browser watching a job: a JobWatcher that keeps the job's events for the page's
// server-sent-event stream (GET /api/jobs/ID/events).
//
// Every state change is kept, in order; progress and preview frames are coalesced: at most one
// progress report and one frame wait after the last state change, a newer one replacing the
// waiting one. So a browser that reads slowly (or not at all) skips frames, holds at most one
// frame (shared with the job, never copied), and never slows the render or other viewers. The
// frame is encoded to JSON (its PNGs base64) on the HTTP thread that sends it, not under the
// job's lock.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <string>

#include "job.h"

namespace partita::server::dashboard {

class JobEventStream : public JobWatcher {
  public:
    /// One server-sent event: `event: NAME` and one line of JSON data.
    struct Event {
        std::string name;  // "state", "progress", "frame", "end"
        std::string data;
    };
    enum class Next { Event, Timeout, End };

    void onState(const pb::Job& job) override;
    void onProgress(const pb::Progress& progress) override;
    void onFrame(std::shared_ptr<const PreviewFrameData> frame) override;
    void onClose(const grpc::Status& status) override;

    /// Waits up to `timeout` for the next event. End once the terminal state has been handed
    /// out with everything queued before it (its final frame), or when the job closed the watch
    /// (then an "end" event carrying the reason comes first).
    Next next(std::chrono::milliseconds timeout, Event& out);

  private:
    struct Item {
        enum Kind { State, Progress, Frame } kind;
        pb::Job job;                                    // State
        pb::Progress progress;                          // Progress
        std::shared_ptr<const PreviewFrameData> frame;  // Frame
    };
    /// The waiting item of `kind` after the last state change, or null.
    Item* pendingAfterLastState(Item::Kind kind);
    static Event render(Item& item);

    std::mutex mutex_;
    std::condition_variable ready_;
    std::deque<Item> queue_;
    bool terminalQueued_ = false;
    bool closed_ = false, closeSent_ = false;
    grpc::Status closeStatus_;
};

}  // namespace partita::server::dashboard
