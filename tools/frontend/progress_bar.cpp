#include "frontend/progress_bar.h"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "algorithm.h"

namespace partita {

ProgressBar::ProgressBar(bool interactive, std::FILE* out) : interactive_(interactive), out_(out) {}

bool ProgressBar::stderrIsTerminal() { return isatty(STDERR_FILENO) == 1; }

namespace {

struct TerminalSize {
    size_t columns = 80, rows = 0;  // rows 0: unknown
};

/// The size of the terminal on `fd`: its width however narrow (anything wider would wrap, and a
/// wrapped line cannot be redrawn in place), 80 columns when it cannot be told.
TerminalSize terminalSize(int fd) {
    TerminalSize size;
    winsize w{};
    if (ioctl(fd, TIOCGWINSZ, &w) == 0) {
        if (w.ws_col > 0) size.columns = w.ws_col;
        size.rows = w.ws_row;
    }
    return size;
}

/// The lines of a partition table as drawn above the bar: cut to `columns`, and when they do not
/// all fit above the bar on a terminal of `rows` (0: unknown) the first ones, "  ... N more" and
/// the last (the complement), or none when not even three fit. (Moving up past the top of the
/// screen stops there: a taller table would be drawn again lower each time, its first lines
/// scrolled into the history.)
std::vector<std::string> tableLines(const std::string& table, size_t columns, size_t rows) {
    std::vector<std::string> lines;
    for (size_t start = 0; start < table.size();) {
        size_t end = table.find('\n', start);
        lines.push_back(table.substr(start, end - start));
        start = end + 1;
    }
    if (rows > 0 && lines.size() > rows - 1) {
        const size_t room = rows - 1;
        if (room < 3) {
            lines.clear();
        } else {
            const std::string last = lines.back();
            const size_t hidden = lines.size() - room + 1;
            lines.resize(room - 2);
            lines.push_back("  ... " + std::to_string(hidden) + " more");
            lines.push_back(last);
        }
    }
    for (std::string& line : lines)
        if (line.size() > columns) line.resize(columns);
    return lines;
}

}  // namespace

std::string humanCount(double v) {
    char buf[32];
    if (v >= 1e9)
        std::snprintf(buf, sizeof buf, "%.2f G", v / 1e9);
    else if (v >= 1e6)
        std::snprintf(buf, sizeof buf, "%.2f M", v / 1e6);
    else if (v >= 1e3)
        std::snprintf(buf, sizeof buf, "%.1f k", v / 1e3);
    else
        std::snprintf(buf, sizeof buf, "%.0f ", v);
    return buf;
}

std::string humanDuration(double s) {
    char buf[32];
    if (!(s >= 0) || !std::isfinite(s)) return "?";
    if (s >= 3600)
        std::snprintf(buf, sizeof buf, "%dh%02dm", int(s / 3600), int(std::fmod(s, 3600) / 60));
    else if (s >= 60)
        std::snprintf(buf, sizeof buf, "%dm%02ds", int(s / 60), int(std::fmod(s, 60)));
    else
        std::snprintf(buf, sizeof buf, "%.1fs", s);
    return buf;
}

std::string acceptanceText(const RenderProgress& p) {
    static const std::string prefix = "acceptance_";
    std::string out;
    for (const auto& [key, value] : p.values) {
        if (key.rfind(prefix, 0) != 0) continue;
        std::string name = key.substr(prefix.size());
        if (name == "bidirectional") name = "bidir";
        if (name == "multi_chain") name = "multi";
        char buf[64];
        std::snprintf(buf, sizeof buf, " %s %.2f", name.c_str(), value);
        out += buf;
    }
    return out.empty() ? out : "acc" + out;
}

std::string partitionTable(const RenderProgress& p) {
    if (p.partitions.empty()) return "";
    size_t width = 9;  // "partition"
    for (const auto& part : p.partitions) width = std::max(width, part.type.size());
    width = std::min<size_t>(width, 40);
    // A "move" column where the algorithm chose one per partition (guided).
    bool moves = false;
    for (const auto& part : p.partitions) moves = moves || !part.move.empty();
    auto row = [&](const std::string& move) {
        return moves ? "  " + (move.empty() ? std::string("-") : move.substr(0, 8)) + "\n"
                     : std::string("\n");
    };
    char line[256];
    std::snprintf(line, sizeof line, "  %-*s  %6s  %9s  %-9s  %5s", int(width), "partition", "P(i)",
                  "b_i", "estimator", "acc");
    std::string out = line + row("move");
    for (const auto& part : p.partitions) {
        // A per-pixel partition has no chains: no acceptance.
        const bool perPixel = part.estimator == "per-pixel";
        char acceptance[16];
        std::snprintf(acceptance, sizeof acceptance, "%5.2f", part.acceptance);
        std::snprintf(line, sizeof line, "  %-*s  %6.3f  %9.3e  %-9s  %5s", int(width),
                      part.type.substr(0, width).c_str(), part.p, part.b,
                      perPixel ? "per-pixel" : "chains", perPixel ? "-" : acceptance);
        out += line + row(part.move);
    }
    return out;
}

void ProgressBar::update(const RenderProgress& p) {
    std::lock_guard lock(mutex_);
    double fraction = p.total > 0 ? std::clamp(p.done / p.total, 0.0, 1.0) : -1;
    if (fraction < 0 && p.etaSeconds >= 0 && p.elapsedSeconds + p.etaSeconds > 0)
        fraction = p.elapsedSeconds / (p.elapsedSeconds + p.etaSeconds);
    std::string rate = humanCount(p.ratePerSecond) + p.unit + "/s";
    std::string eta = p.etaSeconds >= 0 ? humanDuration(p.etaSeconds) : "?";
    std::string acceptance = acceptanceText(p);
    if (!acceptance.empty()) eta += "  " + acceptance;
    if (interactive_) {
        // Room for the acceptance in the phase that reports it (mutations).
        const int width = acceptance.empty() && p.unit != "mutations" ? 30 : 16;
        int filled = fraction >= 0 ? int(fraction * width + 0.5) : 0;
        std::string bar(size_t(filled), '#');
        bar.resize(size_t(width), '.');
        char line[512];
        std::snprintf(line, sizeof line, "%-8s [%s] %5.1f%%  %s  ETA %s", p.phase.c_str(),
                      bar.c_str(), fraction >= 0 ? 100 * fraction : 0.0, rate.c_str(), eta.c_str());
        // One terminal line, never wrapped (a wrapped line cannot be redrawn in place), padded
        // to the width so that nothing of a longer line before it remains.
        std::string text = line;
        const TerminalSize size = terminalSize(fileno(out_));
        const size_t columns = size.columns - 1;
        text.resize(columns, ' ');
        // The partition table above the bar: back to the first line of the one drawn before, or
        // to the start of the bar's line when there was none (the first report of a phase comes
        // before its partitions), clear it and all below, and draw the table and the bar again.
        const std::vector<std::string> table = tableLines(partitionTable(p), columns, size.rows);
        std::string redraw;
        if (drawn_ && (tableLines_ > 0 || !table.empty())) {
            redraw = "\r";
            if (tableLines_ > 0) redraw += "\x1b[" + std::to_string(tableLines_) + "A";
            redraw += "\x1b[J";
        }
        for (const std::string& row : table) redraw += "\r" + row + "\n";
        tableLines_ = int(table.size());
        std::fprintf(out_, "%s\r%s", redraw.c_str(), text.c_str());
        std::fflush(out_);
        drawn_ = true;
        return;
    }
    if (p.done <= 0 && p.ratePerSecond <= 0) return;  // nothing to tell yet
    char line[512];
    std::snprintf(line, sizeof line, "%s: %.1f%%  %s  ETA %s\n", p.phase.c_str(),
                  fraction >= 0 ? 100 * fraction : 0.0, rate.c_str(), eta.c_str());
    // A new phase: the last state of the one before (if not printed yet), then this one at
    // once, so that every phase shows where it started and where it ended.
    const bool newPhase = p.phase != plainPhase_;
    if (newPhase && !pendingPlain_.empty()) std::fputs(pendingPlain_.c_str(), out_);
    plainPhase_ = p.phase;
    pendingPlain_ = line + partitionTable(p);
    auto now = std::chrono::steady_clock::now();
    if (!newPhase && now - lastPlain_ < std::chrono::seconds(5)) return;
    lastPlain_ = now;
    std::fputs(pendingPlain_.c_str(), out_);
    std::fflush(out_);
    pendingPlain_.clear();
}

void ProgressBar::finish() {
    std::lock_guard lock(mutex_);
    if (interactive_ && drawn_) std::fputs("\n", out_);
    drawn_ = false;
    tableLines_ = 0;
    if (!interactive_ && !pendingPlain_.empty()) std::fputs(pendingPlain_.c_str(), out_);
    std::fflush(out_);
    pendingPlain_.clear();
}

}  // namespace partita
