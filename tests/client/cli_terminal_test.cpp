// What the CLI draws on a terminal (a pseudo-terminal of a set size): the progress bar and
// partitioned's partition table redrawn in place above it. The transcript is replayed on a small
// VT100 (terminal.h) to see what a user would see, history included.
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <regex>
#include <set>

#include "algorithm.h"
#include "cli_test_util.h"
#include "frontend/progress_bar.h"
#include "terminal.h"

namespace partita::test {
namespace {

namespace fs = std::filesystem;

const std::regex kHeader(R"(^  partition +P\(i\) +b_i +estimator +acc$)");
const std::regex kPartitionRow(
    R"(^  (\S+) +([01]\.\d{3}) +\d\.\d{3}e[+-]\d{2} +(chains +[01]\.\d{2}|per-pixel +-)$)");

/// Checks every move up of a transcript: "\r ESC[nA ESC[J", from the bar's line back to the
/// first line of the table drawn last, n being the lines written since that table's header (its
/// header and rows; the bar is the line the cursor is on), then cleared to the end of the
/// screen. Returns the n, in order.
std::vector<int> movesUp(const std::string& raw) {
    std::vector<int> out;
    for (const ControlSequence& s : controlSequences(raw)) {
        if (s.final != 'A') continue;
        const int n = std::stoi(s.params);
        out.push_back(n);
        EXPECT_TRUE(s.position > 0 && raw[s.position - 1] == '\r') << "at " << s.position;
        EXPECT_EQ(raw.compare(s.position + s.length, 3, "\x1b[J"), 0)
            << "a move up is followed by an erase below, at " << s.position;
        const size_t header = raw.rfind("\r  partition", s.position);
        EXPECT_NE(header, std::string::npos) << "a move up without a table, at " << s.position;
        if (header == std::string::npos) continue;
        const auto lines =
            std::count(raw.begin() + long(header), raw.begin() + long(s.position), '\n');
        EXPECT_EQ(n, lines) << "moves up over a different number of lines than the table drawn "
                               "last has, at "
                            << s.position;
    }
    return out;
}

/// What is wrong with lines [begin, end) of a terminal while partitioned renders: they must
/// be one bar, or a table (its header, then rows of distinct partitions, the complement last)
/// and the bar below it. "" when nothing is.
std::string renderingScreenProblem(const std::vector<std::string>& lines, size_t begin,
                                   size_t end) {
    if (begin >= end) return "nothing drawn";
    if (lines[end - 1].rfind("render   [", 0) != 0) return "the last line is not the bar";
    if (end - begin == 1) return "";
    if (!std::regex_match(lines[begin], kHeader)) return "not a header: '" + lines[begin] + "'";
    std::set<std::string> types;
    std::smatch m;
    for (size_t i = begin + 1; i + 1 < end; ++i) {
        if (!std::regex_match(lines[i], m, kPartitionRow))
            return "not a partition's row: '" + lines[i] + "'";
        if (!types.insert(m[1].str()).second) return "a partition twice: " + m[1].str();
        if (m[1].str() == "complement" && i + 2 != end) return "the complement is not last";
    }
    if (!types.count("complement")) return "no complement";
    return "";
}

/// The terminal's lines, for assertion messages.
std::string show(const std::vector<std::string>& lines) {
    std::string out = "--- terminal ---\n";
    for (const auto& line : lines) out += "|" + line + "|\n";
    return out;
}

/// A "render" report with `n` partitions, the last the complement.
RenderProgress report(size_t n, double done = 50) {
    RenderProgress p;
    p.phase = "render";
    p.unit = "mutations";
    p.done = done;
    p.total = 100;
    p.ratePerSecond = 1234;
    p.etaSeconds = 1;
    p.values["acceptance_lens"] = 0.5;
    static const char* kTypes[] = {"LDE",   "LDSE", "LSDE", "LDDE",  "LSSE",
                                   "LDSDE", "LE",   "LSE",  "LDSSE", "LSDSE"};
    for (size_t i = 0; i < n; ++i) {
        PartitionProgress part;
        part.type = i + 1 == n ? "complement" : kTypes[i % 10];
        part.p = 1.0 / double(n);
        part.b = 0.01 * double(i + 1);
        part.acceptance = 0.25;
        p.partitions.push_back(part);
    }
    return p;
}

/// A ProgressBar drawing on a pseudo-terminal of `columns` x `rows`; `draw` gets the bar and the
/// terminal as a FILE to write lines around it. Returns the transcript.
template <typename Draw>
std::string drawOnTerminal(int columns, int rows, Draw draw) {
    PseudoTerminal terminal(columns, rows);
    std::FILE* out = ::fdopen(::fcntl(terminal.slave(), F_DUPFD_CLOEXEC, 0), "w");
    if (!out) throw std::runtime_error("fdopen");
    {
        ProgressBar bar(true, out);
        draw(bar, out);
    }
    std::fclose(out);
    return terminal.finish();
}

void say(std::FILE* out, const char* line) {
    std::fprintf(out, "%s\n", line);
    std::fflush(out);
}

/// Whether this machine can open a pseudo-terminal (a minimal chroot may have no /dev/pts):
/// the tests below are skipped, visibly, where it cannot.
bool pseudoTerminalsAvailable() {
    try {
        PseudoTerminal probe(80, 24);
        return true;
    } catch (const std::exception&) {
        return false;
    }
}

#define SKIP_WITHOUT_PTY()                                \
    if (!pseudoTerminalsAvailable())                      \
    GTEST_SKIP() << "no pseudo-terminal on this machine " \
                    "(/dev/pts): the redraw is not tested"

TEST(ProgressBarTerminal, ABarWithoutATableIsRedrawnWithoutEscapes) {
    SKIP_WITHOUT_PTY();
    const std::string raw = drawOnTerminal(80, 24, [](ProgressBar& bar, std::FILE* out) {
        say(out, "above");
        bar.update(report(0, 10));
        bar.update(report(0, 20));
        bar.finish();
        say(out, "below");
    });
    EXPECT_EQ(raw.find('\x1b'), std::string::npos);
    Terminal terminal(80, 24);
    terminal.feed(raw);
    const auto lines = terminal.lines();
    ASSERT_EQ(lines.size(), 3u) << show(lines);
    EXPECT_EQ(lines[0], "above");
    EXPECT_EQ(lines[1].rfind("render   [###.............]  20.0%", 0), 0u) << show(lines);
    EXPECT_EQ(lines[2], "below");
}

TEST(PartitionTable, ShowsEachPartitionsMoveWhereTheAlgorithmChoseOne) {
    RenderProgress p = report(3);
    EXPECT_EQ(partitionTable(p).find("move"), std::string::npos) << partitionTable(p);
    p.partitions[0].move = "guided";
    p.partitions[1].move = "lens";
    p.partitions[2].estimator = "per-pixel";  // no chains: no move
    EXPECT_EQ(partitionTable(p),
              "  partition     P(i)        b_i  estimator    acc  move\n"
              "  LDE          0.333  1.000e-02  chains      0.25  guided\n"
              "  LDSE         0.333  2.000e-02  chains      0.25  lens\n"
              "  complement   0.333  3.000e-02  per-pixel      -  -\n");
}

TEST(ProgressBarTerminal, TheFirstTableReplacesTheBarDrawnBeforeIt) {
    SKIP_WITHOUT_PTY();
    // A phase's first report comes before its partitions; a short render draws its table once.
    const std::string raw = drawOnTerminal(80, 24, [](ProgressBar& bar, std::FILE* out) {
        say(out, "above");
        bar.update(report(0, 0));
        bar.update(report(2, 100));
        bar.finish();
        say(out, "below");
    });
    Terminal terminal(80, 24);
    terminal.feed(raw);
    const auto lines = terminal.lines();
    const std::vector<std::string> expected = {
        "above",
        "  partition     P(i)        b_i  estimator    acc",
        "  LDE          0.500  1.000e-02  chains      0.25",
        "  complement   0.500  2.000e-02  chains      0.25",
        "render   [################] 100.0%  1.2 kmutations/s  ETA 1.0s  acc lens 0.50",
        "below"};
    EXPECT_EQ(lines, expected) << show(lines);
}

TEST(ProgressBarTerminal, TheTableGrowsAndShrinksInPlace) {
    SKIP_WITHOUT_PTY();
    const std::string raw = drawOnTerminal(80, 24, [](ProgressBar& bar, std::FILE* out) {
        say(out, "above");
        bar.update(report(0));  // a phase's first report comes before its partitions
        bar.update(report(3));
        bar.update(report(6));
        bar.update(report(4));
        bar.update(report(0));
        bar.update(report(0));
        bar.update(report(2));
        bar.update(report(3, 100));
        bar.finish();
        say(out, "below");
    });
    // Each move up is over the table drawn before it: 3 + 1, 6 + 1, 4 + 1, 2 + 1 lines.
    EXPECT_EQ(movesUp(raw), (std::vector<int>{4, 7, 5, 3}));
    Terminal terminal(80, 24);
    terminal.feed(raw);
    EXPECT_TRUE(terminal.unexpected.empty());
    const auto lines = terminal.lines();
    // The bar drawn before the first table is gone, nothing of the longer tables remains, the
    // last table and bar stay.
    const std::vector<std::string> expected = {
        "above",
        "  partition     P(i)        b_i  estimator    acc",
        "  LDE          0.333  1.000e-02  chains      0.25",
        "  LDSE         0.333  2.000e-02  chains      0.25",
        "  complement   0.333  3.000e-02  chains      0.25",
        "render   [################] 100.0%  1.2 kmutations/s  ETA 1.0s  acc lens 0.50",
        "below"};
    EXPECT_EQ(lines, expected) << show(lines);
}

TEST(ProgressBarTerminal, ANarrowTerminalCutsTheRowsInsteadOfWrappingThem) {
    SKIP_WITHOUT_PTY();
    // Under 20 columns too: a wrapped row would put the move up short of the table's first line.
    for (int columns : {16, 30}) {
        const std::string raw = drawOnTerminal(columns, 24, [](ProgressBar& bar, std::FILE* out) {
            say(out, "above");
            bar.update(report(0));
            bar.update(report(4));
            bar.update(report(3));
            bar.update(report(3, 100));
            bar.finish();
            say(out, "below");
        });
        EXPECT_EQ(movesUp(raw), (std::vector<int>{5, 4})) << columns;
        Terminal terminal(columns, 24);
        terminal.feed(raw);
        EXPECT_EQ(terminal.wrappedRows(), 0) << columns;
        const auto lines = terminal.lines();
        auto cut = [&](std::string line) {
            line.resize(std::min(line.size(), size_t(columns - 1)));
            line.erase(line.find_last_not_of(' ') + 1);
            return line;
        };
        const std::vector<std::string> expected = {
            "above",
            cut("  partition     P(i)        b_i  estimator    acc"),
            cut("  LDE          0.333  1.000e-02  chains      0.25"),
            cut("  LDSE         0.333  2.000e-02  chains      0.25"),
            cut("  complement   0.333  3.000e-02  chains      0.25"),
            cut("render   [################] 100.0%  1.2 kmutations/s  ETA 1.0s  acc lens 0.50"),
            "below"};
        EXPECT_EQ(lines, expected) << columns << "\n" << show(lines);
    }
}

TEST(ProgressBarTerminal, AShortTerminalShowsTheTableThatFitsAboveTheBar) {
    SKIP_WITHOUT_PTY();
    // 6 rows: 5 lines of table above the bar. A taller table would be drawn lower each time (the
    // move up stops at the top of the screen), leaving its first lines in the history.
    const std::string raw = drawOnTerminal(80, 6, [](ProgressBar& bar, std::FILE* out) {
        say(out, "above");
        bar.update(report(0));
        bar.update(report(10));
        bar.update(report(10));
        bar.update(report(3));
        bar.update(report(10, 100));
        bar.finish();
        say(out, "below");
    });
    EXPECT_EQ(movesUp(raw), (std::vector<int>{5, 5, 4}));
    Terminal terminal(80, 6);
    terminal.feed(raw);
    const auto lines = terminal.lines();
    const std::vector<std::string> expected = {
        "above",
        "  partition     P(i)        b_i  estimator    acc",
        "  LDE          0.100  1.000e-02  chains      0.25",
        "  LDSE         0.100  2.000e-02  chains      0.25",
        "  ... 7 more",
        "  complement   0.100  1.000e-01  chains      0.25",
        "render   [################] 100.0%  1.2 kmutations/s  ETA 1.0s  acc lens 0.50",
        "below"};
    EXPECT_EQ(lines, expected) << show(lines);

    // Too short for a header, a row and the complement above the bar: the bar alone.
    const std::string tiny = drawOnTerminal(80, 3, [](ProgressBar& bar, std::FILE* out) {
        say(out, "above");
        bar.update(report(0));
        bar.update(report(3));
        bar.update(report(3, 100));
        bar.finish();
        say(out, "below");
    });
    EXPECT_EQ(tiny.find('\x1b'), std::string::npos);
    Terminal small(80, 3);
    small.feed(tiny);
    EXPECT_EQ(small.lines(),
              (std::vector<std::string>{
                  "above",
                  "render   [################] 100.0%  1.2 kmutations/s  ETA 1.0s  acc lens 0.50",
                  "below"}))
        << show(small.lines());
}

TEST(CliTerminal, PartitionedRenderRedrawsItsTableInPlace) {
    SKIP_WITHOUT_PTY();
    Daemon daemon;
    TempDir dir;
    constexpr int kColumns = 120, kRows = 40;
    // The options of the plain-mode test (CliRender.PartitionedRendersEndToEndAndWatchShowsThe
    // PartitionTable), with a 3 s budget so that the table is drawn several times: reports go out
    // at most every 0.25 s.
    const std::vector<std::string> part = {
        "--algorithm", "partitioned", "--seconds",   "3",    "--width",   "16", "--height", "12",
        "--k",         "3",           "--bootstrap", "4000", "--prepass", "pt"};
    RunResult r = runInTerminal(concat({PARTITA_CLI_PATH, "--server", daemon.address(), "render",
                                        "cornell-glass", "--out", (dir / "p.exr").string()},
                                       part),
                                kColumns, kRows);
    ASSERT_EQ(r.exitCode, 0) << r.describe() << daemon.log();
    EXPECT_TRUE(fs::exists(dir / "p.exr"));
    const std::string& raw = r.err;

    // The only control sequences are the move up and the erase below.
    for (const ControlSequence& s : controlSequences(raw)) {
        EXPECT_TRUE((s.final == 'A' && !s.params.empty() &&
                     s.params.find_first_not_of("0123456789") == std::string::npos) ||
                    (s.final == 'J' && s.params.empty()))
            << "unexpected sequence at " << s.position << ": ESC[" << s.params << s.final;
    }
    const std::vector<int> ups = movesUp(raw);
    ASSERT_GE(ups.size(), 1u) << "the table was drawn once only, never redrawn\n" << r.describe();

    // The job's id, from its first state line.
    std::smatch m;
    ASSERT_TRUE(std::regex_search(raw, m, std::regex("job (\\w+): "))) << r.describe();
    const std::string job = "job " + m[1].str() + ": ";

    // The screen as it was before each redraw (a "\r" and a move up, or an erase below where no
    // table was drawn yet), that is after each report drawn whole, then as it stays.
    Terminal terminal(kColumns, kRows);
    size_t fed = 0, checked = 0;
    for (const ControlSequence& s : controlSequences(raw)) {
        if (s.position == 0 || raw[s.position - 1] != '\r') continue;
        terminal.feed(std::string_view(raw).substr(fed, s.position - 1 - fed));
        fed = s.position - 1;
        const auto lines = terminal.lines();
        const size_t rendering =
            size_t(std::find(lines.begin(), lines.end(), job + "rendering") - lines.begin());
        if (rendering == lines.size()) continue;
        ++checked;
        EXPECT_EQ(renderingScreenProblem(lines, rendering + 1, lines.size()), "")
            << "before the redraw at " << s.position << "\n"
            << show(lines);
    }
    EXPECT_GE(checked, ups.size()) << r.describe();
    terminal.feed(std::string_view(raw).substr(fed));
    EXPECT_TRUE(terminal.unexpected.empty()) << terminal.unexpected.front();
    const std::vector<std::string> lines = terminal.lines();
    const std::string screen = show(lines);

    // What stays: the state lines (the pre-pass's with its bar when the watch joined before the
    // pre-pass ended: it takes milliseconds; the estimators' pilots, in the same state, redraw
    // it as theirs), then one table under "rendering", the render bar, "done" and the results.
    auto find = [&](const std::string& line) {
        return size_t(std::find(lines.begin(), lines.end(), line) - lines.begin());
    };
    const size_t rendering = find(job + "rendering"), done = find(job + "done");
    ASSERT_LT(rendering + 2, done) << screen;
    if (const size_t prepass = find(job + "prepass"); prepass < lines.size()) {
        EXPECT_EQ(prepass + 2, rendering) << "one pre-pass bar, redrawn in place\n" << screen;
        EXPECT_TRUE(lines.at(prepass + 1).rfind("prepass  [", 0) == 0 ||
                    lines.at(prepass + 1).rfind("pilot    [", 0) == 0)
            << screen;
    }
    EXPECT_EQ(renderingScreenProblem(lines, rendering + 1, done), "") << screen;
    std::vector<std::string> types;
    double sumP = 0;
    for (size_t row = rendering + 2; row < done && std::regex_match(lines[row], m, kPartitionRow);
         ++row) {
        types.push_back(m[1].str());
        sumP += std::stod(m[2].str());
    }
    ASSERT_GE(types.size(), 2u) << "at least one partition and the complement\n" << screen;
    EXPECT_LE(types.size(), 5u) << "K = 3, the direct light and the complement\n" << screen;
    EXPECT_EQ(types.back(), "complement") << screen;
    EXPECT_EQ(std::set<std::string>(types.begin(), types.end()).size(), types.size())
        << "each partition once\n"
        << screen;
    EXPECT_NEAR(sumP, 1.0, 0.005) << screen;
    EXPECT_EQ(lines.at(done + 1).rfind("wrote ", 0), 0u) << screen;
    EXPECT_EQ(std::count_if(lines.begin(), lines.end(),
                            [](const std::string& l) { return std::regex_match(l, kHeader); }),
              1)
        << "no table left behind by a redraw\n"
        << screen;
    // Every line with an ETA is a whole bar: one of the render, at most one of the pre-pass
    // (or the pilots after it).
    size_t renderBars = 0, prepassBars = 0;
    for (const std::string& l : lines) {
        if (l.find("ETA ") == std::string::npos) continue;
        renderBars += l.rfind("render   [", 0) == 0;
        prepassBars += l.rfind("prepass  [", 0) == 0 || l.rfind("pilot    [", 0) == 0;
    }
    EXPECT_EQ(renderBars, 1u) << "no bar left behind by a redraw\n" << screen;
    EXPECT_LE(prepassBars, 1u) << screen;
    EXPECT_EQ(
        std::count_if(lines.begin(), lines.end(),
                      [](const std::string& l) { return l.find("ETA ") != std::string::npos; }),
        long(renderBars + prepassBars))
        << "no piece of a bar left behind\n"
        << screen;
    EXPECT_EQ(std::count(lines.begin(), lines.end(), std::string()), 0) << screen;

    // Every redraw goes back over the whole table: its header and one row per partition.
    for (int n : ups) EXPECT_EQ(n, int(types.size()) + 1) << screen;
    // The bar takes the terminal's width but its last column (so that it never wraps).
    const size_t bar = raw.rfind("\rrender   [");
    ASSERT_NE(bar, std::string::npos);
    EXPECT_EQ(raw.find('\r', bar + 1) - bar - 1, size_t(kColumns - 1)) << screen;
}

}  // namespace
}  // namespace partita::test
