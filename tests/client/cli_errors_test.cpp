// Bad input: every failure exits non-zero with one line "partita: error: ..." on stderr.
#include "cli_test_util.h"

namespace partita::test {
namespace {

namespace fs = std::filesystem;

TEST(CliErrors, MissingSceneFile) {
    expectOneLineError(partita({"render", "/nonexistent/scene.gltf"}), "does not exist");
    expectOneLineError(partita({"render", "/nonexistent/scene.glb", "--server", "127.0.0.1:1"}),
                       "does not exist");
}

TEST(CliErrors, UnknownAlgorithm) {
    Daemon daemon;
    RunResult r = partita(concat(
        {"--server", daemon.address(), "render", "cornell", "--algorithm", "nosuch"}, kTiny));
    expectOneLineError(r, "unknown algorithm 'nosuch'");
    expectOneLineError(r, "(INVALID_ARGUMENT)");
    // The same through a private daemon.
    expectOneLineError(partita(concat({"render", kCornell, "--algorithm", "nosuch"}, kTiny)),
                       "(INVALID_ARGUMENT)");
}

TEST(CliErrors, EnvironmentFlags) {
    expectOneLineError(
        partita(concat({"render", kCornell, "--environment", "/nonexistent/sky.exr"}, kTiny)),
        "cannot read environment image");
    expectOneLineError(partita(concat({"render", "cornell", "--environment-color", "1,1"}, kTiny)),
                       "--environment-color");
    expectOneLineError(partita(concat({"render", "cornell", "--environment", "sky.exr",
                                       "--environment-color", "1,1,1"},
                                      kTiny)),
                       "not both");
}

TEST(CliErrors, BadSweepSyntax) {
    expectOneLineError(partita({"sweep", "cornell", "--sweep", "y8,32"}), "bad --sweep 'y8,32'");
    expectOneLineError(partita({"sweep", "cornell", "--algorithm", "guided", "--sweep", "y=a,b"}),
                       "y must be a whole number, got 'a'");
    expectOneLineError(partita({"sweep", "cornell", "--sweep", "colour=1,2"}),
                       "algorithm 'pt' ignores colour");
    expectOneLineError(partita({"sweep", "cornell", "--sweep", "spp=1,", "--sweep", "y=1"}),
                       "empty value");
    expectOneLineError(partita({"sweep", "cornell", "--sweep", "spp=1", "--sweep", "spp=2"}),
                       "both --sweep axes");
    expectOneLineError(partita({"sweep", "cornell", "--sweep", "spp=1", "--sweep", "mpp=2"}),
                       "budget");
    expectOneLineError(partita({"sweep", "cornell", "--sweep", "width=0,8"}),
                       "width = 0 must be >= 1");
}

TEST(CliErrors, ServerNotReachable) {
    RunResult r = partita({"--server", "127.0.0.1:1", "jobs"});
    expectOneLineError(r, "cannot reach the server at 127.0.0.1:1");
    expectOneLineError(r, "(UNAVAILABLE)");
    expectOneLineError(partita(concat({"--server", "127.0.0.1:1", "render", "cornell"}, kTiny)),
                       "(UNAVAILABLE)");
}

TEST(CliErrors, UnknownJob) {
    Daemon daemon;
    expectOneLineError(partita({"--server", daemon.address(), "watch", "nosuchjob"}),
                       "(NOT_FOUND)");
    expectOneLineError(partita({"--server", daemon.address(), "get", "nosuchjob"}), "(NOT_FOUND)");
    expectOneLineError(partita({"--server", daemon.address(), "cancel", "nosuchjob"}),
                       "(NOT_FOUND)");
}

TEST(CliErrors, UrisEscapingTheSceneFolderAreRefused) {
    TempDir dir;
    fs::create_directory(dir / "scene");
    std::ofstream(dir / "outside.bin") << "secret";
    auto write = [&](const std::string& name, const std::string& uri) {
        std::ofstream(dir / "scene" / name)
            << R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":6,"uri":")" << uri
            << R"("}]})";
        return (dir / "scene" / name).string();
    };
    expectOneLineError(partita({"render", write("up.gltf", "../outside.bin")}),
                       "lies outside the scene's folder");
    expectOneLineError(partita({"render", write("abs.gltf", (dir / "outside.bin").string())}),
                       "absolute path");
    expectOneLineError(partita({"render", write("http.gltf", "http://example.com/x.bin")}),
                       "not a relative file name");
    expectOneLineError(partita({"render", write("missing.gltf", "missing.bin")}), "does not exist");
    fs::create_symlink(dir / "outside.bin", dir / "scene" / "link.bin");
    expectOneLineError(partita({"render", write("link.gltf", "link.bin")}), "outside");
}

TEST(CliErrors, BadCommandLinesAndMisuse) {
    RunResult noScene = partita({"render"});
    expectOneLineError(noScene, "scene");
    EXPECT_EQ(noScene.exitCode, 2);
    expectOneLineError(partita({"frobnicate"}), "frobnicate");
    expectOneLineError(partita(concat({"render", "cornell", "--detach"}, kTiny)),
                       "--detach needs --server");
    expectOneLineError(partita({"watch", "abc"}), "needs --server");
    expectOneLineError(partita({"render", "cornell", "--spp", "0"}), "budget");
    expectOneLineError(partita({"render", "cornell", "--spp", "1", "--mpp", "1"}), "excludes");
    expectOneLineError(partita({"render", kCornell, "--out", "/nonexistent/dir/x.exr"}),
                       "does not exist");
    expectOneLineError(
        partita({"--token-file", "/nonexistent/token", "--server", "127.0.0.1:1", "jobs"}),
        "token file");
}

TEST(CliErrors, PartitadNotFound) {
    expectOneLineError(partita({"jobs"}, {{"PARTITA_PARTITAD", "/nonexistent/partitad"}}),
                       "PARTITA_PARTITAD");
}

}  // namespace
}  // namespace partita::test
