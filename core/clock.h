// The monotonic clock the renderer times its phases with (budgets, previews, statistics).
#pragma once

#include <chrono>

namespace partita {

using Clock = std::chrono::steady_clock;

/// When a phase must end; Clock::time_point::max(): never (a samples or mutations budget).
using Deadline = Clock::time_point;
inline constexpr Deadline kNoDeadline = Clock::time_point::max();

/// Seconds from `t` to now.
inline double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

}  // namespace partita
