#include "job.h"

#include <algorithm>

#include "text.h"

namespace partita::server {

namespace {

int rank(pb::JobState s) {
    switch (s) {
        case pb::JOB_STATE_QUEUED:
            return 0;
        case pb::JOB_STATE_LOADING:
            return 1;
        case pb::JOB_STATE_PREPASS:
            return 2;
        case pb::JOB_STATE_RENDERING:
            return 3;
        default:
            return 4;
    }
}

bool allowed(pb::JobState from, pb::JobState to) {
    if (isTerminal(from) || from == pb::JOB_STATE_UNSPECIFIED) return false;
    if (to == pb::JOB_STATE_QUEUED) return isActive(from);  // re-queued by a shutdown
    if (isTerminal(to)) return true;
    return rank(to) > rank(from);
}

constexpr double kProgressIntervalSeconds = 0.25;

/// Errors and notes echo loader messages, which may quote the (hostile) scene: keep them valid
/// UTF-8, without control characters, and bounded.
std::string boundedText(const std::string& s) { return s.empty() ? s : quoteInput(s, 2000); }

}  // namespace

bool isTerminal(pb::JobState s) {
    return s == pb::JOB_STATE_DONE || s == pb::JOB_STATE_FAILED || s == pb::JOB_STATE_CANCELLED;
}

bool isActive(pb::JobState s) {
    return s == pb::JOB_STATE_LOADING || s == pb::JOB_STATE_PREPASS || s == pb::JOB_STATE_RENDERING;
}

std::string stateName(pb::JobState s) {
    std::string name = pb::JobState_Name(s);
    constexpr std::string_view prefix = "JOB_STATE_";
    if (name.rfind(prefix, 0) == 0) name = name.substr(prefix.size());
    return name.empty() ? std::to_string(int(s)) : name;
}

int64_t nowUnixMs() {
    return std::chrono::duration_cast<std::chrono::milliseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
}

pb::Progress toProto(const RenderProgress& p) {
    pb::Progress out;
    out.set_phase(p.phase);
    out.set_done(p.done);
    out.set_total(p.total);
    out.set_unit(p.unit);
    out.set_rate_per_second(p.ratePerSecond);
    out.set_eta_seconds(p.etaSeconds);
    out.set_elapsed_seconds(p.elapsedSeconds);
    for (const auto& [name, value] : p.values) (*out.mutable_values())[name] = value;
    for (const auto& part : p.partitions) {
        pb::PartitionStats* s = out.add_partitions();
        s->set_type(part.type);
        s->set_acceptance(part.acceptance);
        s->set_b(part.b);
        s->set_p(part.p);
        s->set_gamma(part.gamma);
        s->set_estimator(part.estimator);
        s->set_move(part.move);
    }
    return out;
}

Job::Job(pb::Job record, int64_t sequence)
    : id_(record.id()), sequence_(sequence), spec_(record.spec()), record_(std::move(record)) {}

pb::Job Job::snapshot() const {
    std::lock_guard lock(mutex_);
    return record_;
}

pb::JobState Job::state() const {
    std::lock_guard lock(mutex_);
    return record_.state();
}

bool Job::transition(pb::JobState next, const std::string& error, const Persist& persist,
                     const std::string& note, const std::map<std::string, double>* stats) {
    std::lock_guard lock(mutex_);
    if (!allowed(record_.state(), next)) return false;
    pb::Job updated = record_;
    updated.set_state(next);
    if (next == pb::JOB_STATE_QUEUED) {
        // Back in the queue: nothing failed. Why it was re-queued is a note, not an error.
        updated.clear_error();
        updated.set_note(boundedText(note));
    } else {
        updated.set_error(boundedText(error));
        if (!note.empty()) updated.set_note(boundedText(note));
    }
    int64_t now = nowUnixMs();
    if (next == pb::JOB_STATE_LOADING) {
        updated.set_started_unix_ms(now);
        updated.set_finished_unix_ms(0);
        updated.clear_progress();
    } else if (next == pb::JOB_STATE_QUEUED) {
        updated.set_started_unix_ms(0);
    } else if (isTerminal(next)) {
        updated.set_finished_unix_ms(now);
    }
    if (stats) {
        updated.mutable_stats()->clear();
        for (const auto& [k, v] : *stats) (*updated.mutable_stats())[k] = v;
    }
    if (persist) persist(*this, updated, note);
    // The latest progress of the phase that ends (a phase's last report, say 100%, often comes
    // within the throttle interval of the one before) reaches watchers before the next state.
    if (progressPending_ && record_.has_progress() && next != pb::JOB_STATE_LOADING)
        for (const auto& w : watchers_) w.watcher->onProgress(record_.progress());
    progressPending_ = false;
    record_ = std::move(updated);
    for (const auto& w : watchers_) w.watcher->onState(record_);
    if (isTerminal(next)) watchers_.clear();  // each watcher ends after the terminal state
    return true;
}

void Job::publishProgress(const RenderProgress& progress) {
    std::lock_guard lock(mutex_);
    auto now = std::chrono::steady_clock::now();
    bool phaseChanged = progress.phase != lastPhase_;
    // The last report of the phase before, held back by the interval: it goes out first, so
    // that a watcher sees where every phase ended (a quick pre-pass before the pilots).
    if (phaseChanged && progressPending_)
        for (const auto& w : watchers_) w.watcher->onProgress(record_.progress());
    *record_.mutable_progress() = toProto(progress);
    if (!phaseChanged &&
        std::chrono::duration<double>(now - lastProgressSent_).count() < kProgressIntervalSeconds) {
        progressPending_ = true;
        return;
    }
    progressPending_ = false;
    lastPhase_ = progress.phase;
    lastProgressSent_ = now;
    for (const auto& w : watchers_) w.watcher->onProgress(record_.progress());
}

void Job::publishFrame(LayeredImage image, bool final) {
    // The frame is built outside the lock (it moves the image); only the hand-over is locked.
    uint64_t sequence;
    {
        std::lock_guard lock(mutex_);
        sequence = ++frameCount_;
    }
    auto frame = std::make_shared<const PreviewFrameData>(sequence, final, std::move(image));
    std::lock_guard lock(mutex_);
    if (latestFrame_ && latestFrame_->sequence() > sequence) return;
    if (latestFrame_ && latestFrame_->encodeSeconds() > 0)
        lastEncodeSeconds_ = latestFrame_->encodeSeconds();
    latestFrame_ = frame;
    for (const auto& w : watchers_)
        if (w.previews) w.watcher->onFrame(frame);
}

bool Job::hasPreviewWatchers() const {
    std::lock_guard lock(mutex_);
    for (const auto& w : watchers_)
        if (w.previews) return true;
    return false;
}

double Job::previewEncodeSeconds() const {
    std::lock_guard lock(mutex_);
    const double latest = latestFrame_ ? latestFrame_->encodeSeconds() : 0;
    return latest > 0 ? latest : lastEncodeSeconds_;
}

void Job::releasePreviewFrame() {
    std::lock_guard lock(mutex_);
    if (latestFrame_ && !latestFrame_->isFinal()) latestFrame_.reset();
}

void Job::keepFinalFrameOnDisk(const std::filesystem::path& resultExr) {
    std::lock_guard lock(mutex_);
    uint64_t sequence =
        latestFrame_ ? latestFrame_->sequence() : std::max<uint64_t>(frameCount_, 1);
    latestFrame_ = std::make_shared<const PreviewFrameData>(sequence, resultExr);
}

void Job::requestCancel(CancelReason reason) {
    CancelReason none = CancelReason::None;
    cancelReason_.compare_exchange_strong(none, reason);
    cancel_.store(true);
}

grpc::Status Job::addWatcher(std::shared_ptr<JobWatcher> watcher, bool previews, int maxWatchers) {
    std::lock_guard lock(mutex_);
    bool finished = isTerminal(record_.state());
    if (int(open_.size()) >= maxWatchers)
        return {grpc::StatusCode::RESOURCE_EXHAUSTED,
                "job " + id_ + " already has " + std::to_string(open_.size()) +
                    " watchers, the limit of this server (--max-watchers)"};
    open_.insert(watcher.get());
    watcher->onState(record_);
    if (previews && latestFrame_) watcher->onFrame(latestFrame_);
    if (!finished) watchers_.push_back({std::move(watcher), previews});
    return grpc::Status::OK;
}

void Job::removeWatcher(const JobWatcher* watcher) {
    std::lock_guard lock(mutex_);
    open_.erase(watcher);
    std::erase_if(watchers_, [&](const WatcherEntry& e) { return e.watcher.get() == watcher; });
}

void Job::closeWatchers(const grpc::Status& status) {
    std::lock_guard lock(mutex_);
    for (const auto& w : watchers_) w.watcher->onClose(status);
    watchers_.clear();
}

}  // namespace partita::server
