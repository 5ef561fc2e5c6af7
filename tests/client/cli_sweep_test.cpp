// partita sweep: a 2x2 grid over spp x max-depth against a reference, and a 1-axis sweep through
// a private daemon.
#include <cmath>

#include "cli_test_util.h"

namespace partita::test {
namespace {

namespace fs = std::filesystem;

TEST(CliSweep, GridAgainstReferenceWritesTableAndCsv) {
    Daemon daemon;
    TempDir dir;
    RunResult ref =
        partita({"--server", daemon.address(), "render", "cornell", "--spp", "8", "--width", "32",
                 "--height", "24", "--out", (dir / "ref.exr").string()});
    ASSERT_EQ(ref.exitCode, 0) << ref.describe();

    RunResult r =
        partita({"--server", daemon.address(), "sweep", "cornell", "--sweep", "spp=1,2", "--sweep",
                 "max-depth=1,2", "--width", "32", "--height", "24", "--reference",
                 (dir / "ref.exr").string(), "--out-dir", (dir / "sw").string()});
    ASSERT_EQ(r.exitCode, 0) << r.describe() << daemon.log();
    auto rows = lines(r.out);
    ASSERT_EQ(rows.size(), 5u) << r.describe();
    EXPECT_EQ(words(rows[0]), (std::vector<std::string>{"spp", "max-depth", "rmse", "relmse",
                                                        "seconds", "state", "file"}));
    const std::vector<std::pair<std::string, std::string>> grid = {
        {"1", "1"}, {"1", "2"}, {"2", "1"}, {"2", "2"}};
    for (size_t i = 0; i < grid.size(); ++i) {
        auto w = words(rows[i + 1]);
        ASSERT_EQ(w.size(), 7u) << rows[i + 1];
        EXPECT_EQ(w[0], grid[i].first);
        EXPECT_EQ(w[1], grid[i].second);
        const double rmse = std::stod(w[2]), relmse = std::stod(w[3]), seconds = std::stod(w[4]);
        EXPECT_TRUE(std::isfinite(rmse) && rmse > 0) << rows[i + 1];
        EXPECT_TRUE(std::isfinite(relmse) && relmse > 0) << rows[i + 1];
        EXPECT_TRUE(std::isfinite(seconds) && seconds >= 0) << rows[i + 1];
        EXPECT_EQ(w[5], "done");
        EXPECT_TRUE(fs::exists(w[6])) << w[6];
        EXPECT_TRUE(fs::exists(fs::path(w[6]).replace_extension(".png")));
    }
    EXPECT_TRUE(fs::exists(dir / "sw" / "spp=1_max-depth=2.exr"));
    auto csv = lines(readText(dir / "sw" / "sweep.csv"));
    ASSERT_EQ(csv.size(), 5u);
    EXPECT_EQ(csv[0], "spp,max-depth,rmse,relmse,seconds,state,file");

    // Every job carries the sweep's label.
    RunResult jobs = partita({"--server", daemon.address(), "jobs", "--label", "sweep:cornell"});
    ASSERT_EQ(jobs.exitCode, 0);
    EXPECT_EQ(lines(jobs.out).size(), 5u) << jobs.describe();
}

TEST(CliSweep, OneAxisThroughPrivateDaemonWithoutReference) {
    TempDir dir;
    RunResult r = partita({"-q", "sweep", "cornell", "--sweep", "seed=1,2", "--width", "8",
                           "--height", "8", "--spp", "1", "--out-dir", (dir / "s").string()});
    ASSERT_EQ(r.exitCode, 0) << r.describe();
    auto rows = lines(r.out);
    ASSERT_EQ(rows.size(), 3u) << r.describe();
    EXPECT_EQ(words(rows[0]), (std::vector<std::string>{"seed", "seconds", "state", "file"}));
    EXPECT_TRUE(fs::exists(dir / "s" / "seed=2.exr"));
}

}  // namespace
}  // namespace partita::test
