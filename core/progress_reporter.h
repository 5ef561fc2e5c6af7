// Turns "n more units done" calls from worker threads into throttled RenderProgress reports
// with rate and ETA, delivered to the observer one at a time.
#pragma once

#include <chrono>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "algorithm.h"

namespace partita {

class ProgressReporter {
  public:
    /// total <= 0 means unknown (time budgets): the ETA then comes from `timeBudgetSeconds`.
    /// Reports the start of the phase (nothing done yet) at once.
    ProgressReporter(RenderObserver& observer, std::string phase, std::string unit, double total,
                     double timeBudgetSeconds = 0, double minIntervalSeconds = 0.1);

    /// Thread-safe. Reports at most once per minimum interval.
    void advance(double units);
    /// Always reports the current state (phase ends, pass ends).
    void flush();
    /// Thread-safe. Replaces the named statistics of the phase (RenderProgress::values); they go
    /// out with the next report.
    void setValues(std::map<std::string, double> values);
    /// Thread-safe. Sets some of the named statistics, keeping the others.
    void mergeValues(const std::map<std::string, double>& values);
    /// Thread-safe. Replaces the per-partition statistics of the phase
    /// (RenderProgress::partitions); they go out with the next report.
    void setPartitions(std::vector<PartitionProgress> partitions);
    double elapsedSeconds() const;
    double done() const;

  private:
    RenderProgress snapshotLocked() const;
    RenderObserver& observer_;
    std::string phase_, unit_;
    double total_, timeBudget_, minInterval_;
    std::chrono::steady_clock::time_point start_, lastReport_;
    mutable std::mutex mutex_;
    double done_ = 0;
    std::map<std::string, double> values_;
    std::vector<PartitionProgress> partitions_;
};

}  // namespace partita
