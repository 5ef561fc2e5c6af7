// A terminal progress bar with rate and ETA for the command-line front ends. On a terminal it
// redraws one line on stderr; otherwise it prints a plain line when work is first reported
// done, then at most every 5 s, and the latest one when the work is over (finish), so that a log
// shows how far it got and never only "0.0% ... ETA ?".
#pragma once

#include <chrono>
#include <mutex>
#include <string>

namespace partita {

struct RenderProgress;

class ProgressBar {
  public:
    explicit ProgressBar(bool interactive);
    static bool stderrIsTerminal();

    void update(const RenderProgress& p);
    /// Ends the bar's line; without a terminal, prints the latest progress if it was not printed.
    void finish();

  private:
    bool interactive_;
    bool drawn_ = false;
    std::mutex mutex_;
    std::chrono::steady_clock::time_point lastPlain_{};
    std::string pendingPlain_;  // the latest plain line not printed yet
};

/// "1.23 M", "456 k" ... for rates and counts.
std::string humanCount(double value);
/// "1h02m", "3m05s", "12.3s".
std::string humanDuration(double seconds);

}  // namespace partita
