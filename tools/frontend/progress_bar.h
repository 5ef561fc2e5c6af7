// A terminal progress bar with rate and ETA for the command-line front ends. On a terminal it
// redraws one line on stderr; otherwise it prints a plain line when work is first reported
// done, then at most every 5 s, and the latest one when the work is over (finish), so that a log
// shows how far it got and never only "0.0% ... ETA ?". An MCMC method's running acceptance
// per mutation type follows the ETA. A report with partitions (partitioned's "render") comes with
// a compact table of them (type, P(i), b_i, running acceptance): on a terminal redrawn in place
// above the bar, otherwise printed with each plain line (at most every 5 s, and at the end).
// On a terminal nothing is ever wrapped (bar and rows are cut to its width), the table never
// takes more lines than there are above the bar (the rows that do not fit are counted in a
// "... N more" row before the last, the complement), so that moving back up to its first line
// always works, and the final table and bar stay on the screen.
#pragma once

#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

namespace partita {

struct RenderProgress;

class ProgressBar {
  public:
    /// Draws on `out` (stderr unless a test says otherwise); `interactive`: `out` is a terminal.
    explicit ProgressBar(bool interactive, std::FILE* out = stderr);
    static bool stderrIsTerminal();

    void update(const RenderProgress& p);
    /// Ends the bar's line; without a terminal, prints the latest progress if it was not printed.
    void finish();

  private:
    bool interactive_;
    std::FILE* out_;
    bool drawn_ = false;
    std::mutex mutex_;
    std::chrono::steady_clock::time_point lastPlain_{};
    std::string plainPhase_;    // the phase of the last plain line
    std::string pendingPlain_;  // the latest plain line (and table) not printed yet
    int tableLines_ = 0;        // lines of the partition table drawn above the bar
};

/// The partitions of a progress report as a small table, one line per partition after a
/// header, each line ending in '\n'; "" when the report has none:
///   partition    P(i)       b_i   acc
///   LDE         0.612  1.23e-01  0.45
std::string partitionTable(const RenderProgress& p);

/// The running acceptance per mutation type of a progress report's values ("acceptance_<name>"),
/// compact: "acc bidir 0.46 caustic 0.12 lens 0.64 multi 0.55"; "" when there is none.
std::string acceptanceText(const RenderProgress& p);

/// "1.23 M", "456 k" ... for rates and counts.
std::string humanCount(double value);
/// "1h02m", "3m05s", "12.3s".
std::string humanDuration(double seconds);

}  // namespace partita
