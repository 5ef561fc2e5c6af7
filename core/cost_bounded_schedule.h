// Work a render does now and then beside its samples (previews, its error estimate), whose
// cost must stay a small share of the render: due the first time, then once `minSeconds` have
// passed since the last time began, and never sooner than `costFactor` times what the last
// time cost (so it takes at most about 1 / costFactor of the time, whatever the image size).
#pragma once

#include <algorithm>

#include "clock.h"

namespace partita {

class CostBoundedSchedule {
  public:
    CostBoundedSchedule(double minSeconds, double costFactor)
        : minSeconds_(minSeconds), costFactor_(costFactor) {}

    /// The seconds between two times now; `extraCost`: seconds the last time cost elsewhere
    /// (another thread's share of it), counted with its own.
    double interval(double extraCost = 0) const {
        return std::max(minSeconds_, costFactor_ * (lastCost_ + extraCost));
    }
    bool due(double extraCost = 0) const {
        return !ran_ || secondsSince(last_) >= interval(extraCost);
    }
    /// Seconds until it is due (0 when due), to size the work before it.
    double untilDue(double extraCost = 0) const {
        return ran_ ? std::max(0.0, interval(extraCost) - secondsSince(last_)) : 0.0;
    }
    /// It ran from `began` until now.
    void ran(Clock::time_point began) {
        ran_ = true;
        last_ = began;
        lastCost_ = secondsSince(began);
    }

  private:
    double minSeconds_, costFactor_;
    bool ran_ = false;
    Clock::time_point last_{};
    double lastCost_ = 0;  // seconds the last time took
};

}  // namespace partita
