// The error of an MCMC render (mlt, partitioned, guided) estimated while its chains run, and its
// stop at a target error (issue #26). The algorithm says how to estimate (an Estimator: the
// combined image's relative RMSE and, by name, its parts', e.g. each partition's, made of its
// chains' two halves (ChainRunner::halvesError), its normalising constants' errors and its
// per-pixel parts' variances; half_split_error.h). After a round of the chains the monitor
// estimates when an estimate is due, puts it into the phase's progress values
// ("error_estimate" and the parts' names) and asks the runner to stop once the combined
// estimate is at or below the target, trusted from kMinMutationsPerPixel mutations per pixel.
//
// Due: after every round when a mutation budget has a target (rounds are fixed mutations: the
// stop depends on the seed and the budget only, not on timing or threads); otherwise at most
// every half second and at most 5% of the time (an estimate resolves films).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>

#include "algorithm.h"
#include "clock.h"
#include "cost_bounded_schedule.h"

namespace partita {

class ChainRunner;
class ProgressReporter;

class ChainErrorMonitor {
  public:
    static constexpr double kMinMutationsPerPixel = 2;

    struct Estimate {
        double combined = -1;  // the combined image's relative RMSE; < 0: none yet
        /// What is compared with the target when not the combined estimate (>= 0): a part's
        /// own share while another part is still to come (mlt's chains before its direct light).
        double target = -1;
        std::map<std::string, double> parts;
        double forTarget() const { return target >= 0 ? target : combined; }
        /// Into the phase's progress values: the parts, and "error_estimate" when there is a
        /// combined estimate (nothing when there is neither).
        void publish(ProgressReporter& progress) const;
    };
    using Estimator = std::function<Estimate()>;

    /// `targetError` 0: never stop; the settings give the budget's kind and the image's pixels
    /// (the trust rule's mutations).
    ChainErrorMonitor(const RenderSettings& settings, double targetError, Estimator estimator);

    /// The rule for an estimate that is not needed every round: at most every half second and
    /// at most 5% of the time. (The per-pixel partitions' and the sample passes' estimates
    /// follow it too.)
    static CostBoundedSchedule estimateSchedule() { return {0.5, 20}; }

    /// After a round of `runner`'s chains: estimate when due, publish, stop at the target.
    void afterRound(ChainRunner& runner, ProgressReporter& progress);
    /// Estimates now (the final image's error, after the chains and any per-pixel part).
    void estimateNow();
    const Estimate& latest() const { return latest_; }
    bool reachedTarget() const { return reachedTarget_; }
    /// "error_estimate" and its parts when there is an estimate, and "reached_target_error"
    /// when a target was set.
    void addStats(RenderStats& st) const;

  private:
    bool due() const;

    double targetError_;
    bool everyRound_;
    double minMutations_;
    Estimator estimator_;
    Estimate latest_;
    bool reachedTarget_ = false;
    CostBoundedSchedule schedule_ = estimateSchedule();
};

}  // namespace partita
