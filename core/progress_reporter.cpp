#include "progress_reporter.h"

#include <algorithm>

#include "clock.h"

namespace partita {

ProgressReporter::ProgressReporter(RenderObserver& observer, std::string phase, std::string unit,
                                   double total, double timeBudgetSeconds,
                                   double minIntervalSeconds)
    : observer_(observer),
      phase_(std::move(phase)),
      unit_(std::move(unit)),
      total_(total),
      timeBudget_(timeBudgetSeconds),
      minInterval_(minIntervalSeconds),
      start_(Clock::now()),
      lastReport_(start_) {
    // The phase's start is news in itself (a service moves the job to the phase's state), and it
    // must reach the observer before anything the phase produces, such as a first preview.
    observer_.onProgress(snapshotLocked());
}

double ProgressReporter::elapsedSeconds() const { return secondsSince(start_); }

double ProgressReporter::done() const {
    std::lock_guard lock(mutex_);
    return done_;
}

RenderProgress ProgressReporter::snapshotLocked() const {
    RenderProgress p;
    p.phase = phase_;
    p.unit = unit_;
    p.done = done_;
    p.total = total_;
    p.elapsedSeconds = elapsedSeconds();
    p.values = values_;
    p.partitions = partitions_;
    p.ratePerSecond = p.elapsedSeconds > 0 ? done_ / p.elapsedSeconds : 0;
    if (total_ > 0 && p.ratePerSecond > 0)
        p.etaSeconds = std::max(0.0, (total_ - done_) / p.ratePerSecond);
    else if (timeBudget_ > 0)
        p.etaSeconds = std::max(0.0, timeBudget_ - p.elapsedSeconds);
    return p;
}

void ProgressReporter::advance(double units) {
    std::lock_guard lock(mutex_);
    done_ += units;
    auto now = Clock::now();
    if (std::chrono::duration<double>(now - lastReport_).count() < minInterval_) return;
    lastReport_ = now;
    observer_.onProgress(snapshotLocked());
}

void ProgressReporter::setValues(std::map<std::string, double> values) {
    std::lock_guard lock(mutex_);
    values_ = std::move(values);
}

void ProgressReporter::mergeValues(const std::map<std::string, double>& values) {
    std::lock_guard lock(mutex_);
    for (const auto& [name, value] : values) values_[name] = value;
}

void ProgressReporter::setPartitions(std::vector<PartitionProgress> partitions) {
    std::lock_guard lock(mutex_);
    partitions_ = std::move(partitions);
}

void ProgressReporter::flush() {
    std::lock_guard lock(mutex_);
    lastReport_ = Clock::now();
    observer_.onProgress(snapshotLocked());
}

}  // namespace partita
