// One render job: its record (spec, state, times, progress, statistics), its state machine, its
// cancel flag, and the fan-out of its events to watchers.
//
// States: QUEUED -> LOADING -> (PREPASS) -> RENDERING -> DONE | FAILED | CANCELLED; an active job
// goes back to QUEUED when the daemon stops under it. Every transition is persisted (through the
// Persist callback) before watchers hear of it, so a watcher that saw DONE can fetch the result.
//
// Watchers get every state change in order, the latest progress and the latest preview frame:
// a slow watcher skips intermediate progress and frames, never a state change or the final
// frame. Nothing here waits for a watcher: events are handed over under a short lock.
#pragma once

#include <grpcpp/support/status.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "algorithm.h"
#include "preview_frame.h"
#include "proto.h"

namespace partita::server {

/// Receives a job's events. Called with the job's lock held: implementations only queue.
class JobWatcher {
  public:
    virtual ~JobWatcher() = default;
    virtual void onState(const pb::Job& job) = 0;
    virtual void onProgress(const pb::Progress& progress) = 0;
    virtual void onFrame(std::shared_ptr<const PreviewFrameData> frame) = 0;
    /// No more events will come; end the watch with `status` (daemon shutting down, job deleted).
    virtual void onClose(const grpc::Status& status) = 0;
};

enum class CancelReason { None, User, Shutdown };

bool isTerminal(pb::JobState state);
bool isActive(pb::JobState state);  // LOADING, PREPASS or RENDERING
/// "QUEUED", "RENDERING", ...
std::string stateName(pb::JobState state);
int64_t nowUnixMs();

class Job {
  public:
    /// Persists a new record before it takes effect; throws to refuse it (e.g. disk error).
    using Persist =
        std::function<void(const Job& job, const pb::Job& next, const std::string& note)>;

    /// `record.spec` carries no scene bytes. `sequence` orders jobs of equal priority.
    Job(pb::Job record, int64_t sequence);

    const std::string& id() const { return id_; }
    int64_t sequence() const { return sequence_; }
    int priority() const { return spec_.priority(); }
    const pb::JobSpec& spec() const { return spec_; }
    pb::Job snapshot() const;
    pb::JobState state() const;

    /// Moves to `next` when that is a valid step from the current state; returns false (and does
    /// nothing) otherwise. `error` becomes the record's error (cleared when empty); `stats`, when
    /// given, replaces its statistics. `note` is logged with the transition; going back to QUEUED
    /// (a re-queue, never an error) it also becomes the record's `note` and the record's error is
    /// cleared whatever `error` says; on other steps a non-empty `note` (a warning such as "the
    /// scene has no light") becomes the record's note too. The record keeps its latest note through
    /// later states. Times are kept: started on LOADING, finished on a terminal state. Throws what
    /// `persist` throws, leaving the job unchanged.
    bool transition(pb::JobState next, const std::string& error, const Persist& persist,
                    const std::string& note = {},
                    const std::map<std::string, double>* stats = nullptr);

    /// Records the progress; passes it to watchers at most every 0.25 s (and on a phase change).
    /// A report held back by that interval goes out before the next state change, so watchers
    /// always see the last progress of a phase.
    void publishProgress(const RenderProgress& progress);
    /// A new preview (or, with final, the result image).
    void publishFrame(LayeredImage image, bool final);
    /// Lets go of the latest preview frame before the final image is written: one dense copy of
    /// every layer fewer at the job's memory peak (job_memory.h). Watchers still get the final
    /// frame when it is published; one joining in between gets the state first, then that frame.
    void releasePreviewFrame();
    /// Replaces the in-memory final frame by one read back from the result file when asked for,
    /// so that finished jobs hold no images in memory.
    void keepFinalFrameOnDisk(const std::filesystem::path& resultExr);

    /// Whether some open watcher asked for previews (a render makes none while none does).
    bool hasPreviewWatchers() const;
    /// Seconds the last preview frame whose PNGs were encoded took to encode.
    double previewEncodeSeconds() const;

    /// Raises the cancel flag the render polls; the first reason given sticks.
    void requestCancel(CancelReason reason);
    CancelReason cancelReason() const { return cancelReason_.load(); }
    const std::atomic<bool>& cancelFlag() const { return cancel_; }
    bool cancelRequested() const { return cancel_.load(); }

    /// Adds a watcher and immediately gives it the current state and the latest frame. A watcher
    /// of a finished job gets those and nothing more. RESOURCE_EXHAUSTED beyond `maxWatchers`
    /// open streams, whatever the job's state: a watcher counts until removeWatcher.
    grpc::Status addWatcher(std::shared_ptr<JobWatcher> watcher, bool previews, int maxWatchers);
    void removeWatcher(const JobWatcher* watcher);
    /// Ends every watch with `status`.
    void closeWatchers(const grpc::Status& status);

    /// "[job <id>]", the prefix of every log line about this job.
    std::string tag() const { return "[job " + id_ + "]"; }

  private:
    struct WatcherEntry {
        std::shared_ptr<JobWatcher> watcher;
        bool previews;
    };

    const std::string id_;
    const int64_t sequence_;
    const pb::JobSpec spec_;
    mutable std::mutex mutex_;
    pb::Job record_;
    std::vector<WatcherEntry> watchers_;  // those that still get events
    std::set<const JobWatcher*> open_;    // every accepted watcher whose stream is open
    std::shared_ptr<const PreviewFrameData> latestFrame_;
    double lastEncodeSeconds_ = 0;  // of the last frame replaced after its PNGs were encoded
    uint64_t frameCount_ = 0;
    std::chrono::steady_clock::time_point lastProgressSent_{};
    std::string lastPhase_;
    bool progressPending_ = false;  // the record's progress is newer than the watchers' last
    std::atomic<bool> cancel_{false};
    std::atomic<CancelReason> cancelReason_{CancelReason::None};
};

/// The Progress message of a core progress report.
pb::Progress toProto(const RenderProgress& progress);

}  // namespace partita::server
