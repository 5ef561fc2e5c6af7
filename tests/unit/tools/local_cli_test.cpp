// partita-local as a user runs it: renders write an EXR with type layers and a PNG; bad input
// prints exactly one line on stderr and exits non-zero.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "image_bits.h"
#include "image_io.h"

namespace fs = std::filesystem;

namespace partita {
namespace {

struct RunResult {
    int exitCode = -1;
    std::string stderrText;
};

RunResult runLocal(const std::string& args) {
    fs::path dir = fs::temp_directory_path() / ("partita-local-test-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    fs::path errFile = dir / "stderr.txt";
    std::string cmd =
        std::string(PARTITA_LOCAL_BIN) + " " + args + " 2>" + errFile.string() + " >/dev/null";
    int status = std::system(cmd.c_str());
    RunResult r;
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream in(errFile);
    r.stderrText.assign(std::istreambuf_iterator<char>(in), {});
    return r;
}

int lineCount(const std::string& s) {
    int n = 0;
    for (char c : s) n += c == '\n';
    return n;
}

fs::path tempDir() {
    fs::path dir = fs::temp_directory_path() / ("partita-local-out-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return dir;
}

TEST(LocalCli, RendersTheShippedSceneToExrAndPng) {
    fs::path out = tempDir() / "cornell.exr";
    RunResult r =
        runLocal(std::string(PARTITA_SCENES_DIR) + "/cornell-glass/cornell-glass.gltf --quiet" +
                 " --width 32 --height 24 --spp 2 --out " + out.string());
    // `render` is the subcommand: the line above lacks it on purpose to check the error path.
    EXPECT_NE(r.exitCode, 0);
    r = runLocal("render " + std::string(PARTITA_SCENES_DIR) +
                 "/cornell-glass/cornell-glass.gltf --quiet" +
                 " --width 32 --height 24 --spp 2 --out " + out.string());
    ASSERT_EQ(r.exitCode, 0) << r.stderrText;
    LayeredImage img = readExr(out);
    EXPECT_EQ(img.combined.width, 32);
    EXPECT_EQ(img.combined.height, 24);
    EXPECT_FALSE(img.layers.empty());
    EXPECT_GT(luminance(img.combined.mean()), 0.0f);
    EXPECT_TRUE(fs::exists(fs::path(out).replace_extension(".png")));
}

void expectOneLineError(const std::string& args, const std::string& needle) {
    RunResult r = runLocal(args);
    EXPECT_NE(r.exitCode, 0) << args;
    EXPECT_EQ(lineCount(r.stderrText), 1) << r.stderrText;
    EXPECT_NE(r.stderrText.find(needle), std::string::npos) << r.stderrText;
}

TEST(LocalCli, BadInputIsOneLineAndNonZero) {
    std::string scene = std::string(PARTITA_SCENES_DIR) + "/cornell/cornell.gltf";
    fs::path out = tempDir() / "x.exr";
    expectOneLineError("render /nonexistent/scene.gltf --quiet --out " + out.string(),
                       "scene.gltf");
    expectOneLineError("render " + scene + " --quiet --width -5 --out " + out.string(),
                       "width = -5 must be >= 1");
    expectOneLineError("render " + scene + " --quiet --radius 5 --out " + out.string(),
                       "unknown parameter 'radius' for pt");
    expectOneLineError("render " + scene + " --quiet --param strength=1 --out " + out.string(),
                       "unknown parameter 'strength' for pt");
    expectOneLineError(
        "render " + scene + " --quiet --width 100000 --height 100000 --out " + out.string(),
        "resolution");
    expectOneLineError("render " + scene + " --quiet --algorithm warp-drive --out " + out.string(),
                       "warp-drive");
    expectOneLineError("render " + scene + " --quiet --spp 0 --out " + out.string(), "budget");
    expectOneLineError("render " + scene + " --quiet --camera nope --out " + out.string(), "nope");
    fs::path bad = tempDir() / "broken.gltf";
    std::ofstream(bad) << "{ \"asset\": {\"version\": \"2.0\"}, \"buffers\": [ {\"byteLength\": 99";
    expectOneLineError("render " + bad.string() + " --quiet --out " + out.string(), "error");
    expectOneLineError(
        "render " + scene + " --quiet --out /nonexistent-dir/x.exr --width 8 --height 8 --spp 1",
        "nonexistent-dir");
}

// The scale-out commands as a cluster runs them: plan once, each shard from its array index in
// the environment, merge in any order; the EXR equals the one-process render bit for bit.
TEST(LocalCli, ShardsFromTheArrayIndexMergeIntoTheOneProcessRender) {
    const std::string scene = std::string(PARTITA_SCENES_DIR) + "/cornell-glass/cornell-glass.gltf";
    const std::string job = " --algorithm mlt --mpp 4 --bootstrap 3000 --width 24 --height 18";
    const fs::path dir = tempDir();
    const std::string one = (dir / "one.exr").string(), plan = (dir / "job.plan").string();
    ASSERT_EQ(runLocal("render " + scene + job + " --quiet --out " + one).exitCode, 0);
    RunResult r = runLocal("plan " + scene + job + " --quiet --shards 3 --out " + plan);
    ASSERT_EQ(r.exitCode, 0) << r.stderrText;
    std::string shards;
    for (int i : {2, 0, 1}) {
        const std::string out = (dir / ("s" + std::to_string(i) + ".shard")).string();
        const char* variable = i == 1 ? "JOB_COMPLETION_INDEX" : "SLURM_ARRAY_TASK_ID";
        r = runLocal("render --plan " + plan + " --quiet --out " + out);
        EXPECT_NE(r.exitCode, 0);  // no index anywhere
        ::setenv(variable, std::to_string(i).c_str(), 1);
        r = runLocal("render --plan " + plan + " --quiet --out " + out);
        ::unsetenv(variable);
        ASSERT_EQ(r.exitCode, 0) << r.stderrText;
        shards += " " + out;
    }
    const std::string merged = (dir / "merged.exr").string();
    r = runLocal("merge --plan " + plan + shards + " --quiet --out " + merged);
    ASSERT_EQ(r.exitCode, 0) << r.stderrText;
    test::expectSameBits(readExr(one), readExr(merged));

    // Wrong, missing and mismatched shards: one line each.
    const std::string s0 = (dir / "s0.shard").string(), s1 = (dir / "s1.shard").string();
    expectOneLineError("merge --plan " + plan + " " + s0 + " " + s1 + " --out " + merged,
                       "missing shards 2 of 3");
    const fs::path cut = dir / "cut.shard";
    fs::copy_file(s0, cut, fs::copy_options::overwrite_existing);
    fs::resize_file(cut, fs::file_size(cut) / 2);
    expectOneLineError("merge --plan " + plan + " " + cut.string() + " --out " + merged,
                       "truncated or damaged");
    const std::string otherPlan = (dir / "other.plan").string();
    ASSERT_EQ(runLocal("plan " + scene + job + " --seed 99 --quiet --shards 3 --out " + otherPlan)
                  .exitCode,
              0);
    expectOneLineError("merge --plan " + otherPlan + shards + " --out " + merged, "another plan");
    expectOneLineError("render --plan " + plan + " --shard 3 --out " + s0, "out of range");
    expectOneLineError("render --plan " + s0 + " --shard 0 --out " + s0,
                       "not a Partita shard plan");
    expectOneLineError("plan " + scene + " --seconds 2 --shards 2 --out " + plan, "time budget");
}

}  // namespace
}  // namespace partita
