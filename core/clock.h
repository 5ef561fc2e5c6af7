// The monotonic clock the renderer times its phases with (budgets, previews, statistics).
#pragma once

#include <chrono>

namespace partita {

using Clock = std::chrono::steady_clock;

/// Seconds from `t` to now.
inline double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

}  // namespace partita
