// What a new user runs into: a daemon started a moment ago, the server's own limits, logs without
// a terminal, Ctrl-C during a render, sweeps that cannot mean anything, --version.
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "cli_test_util.h"

namespace partita::test {
namespace {

namespace fs = std::filesystem;

/// A loopback port that was free a moment ago.
int freePort() {
    int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
    socklen_t len = sizeof addr;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
    ::close(fd);
    return ntohs(addr.sin_port);
}

bool portIsFree(int port) {
    int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = htons(uint16_t(port));
    bool free = ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
    ::close(fd);
    return free;
}

RunResult shell(const std::string& script, double timeout = 120) {
    return runProgram({"/bin/bash", "-c", script}, {}, timeout);
}

std::string q(const fs::path& p) {
    std::string out = "'";  // appended, not "'" + ...: GCC 12 warns falsely (-Wrestrict)
    out.append(p.string()).append("'");
    return out;
}

TEST(CliNewUser, VersionFlag) {
    RunResult r = partita({"--version"});
    EXPECT_EQ(r.exitCode, 0) << r.describe();
    EXPECT_NE(r.out.find("0."), std::string::npos) << r.describe();
}

TEST(CliNewUser, WaitsForADaemonThatIsStillStarting) {
    TempDir dir;
    const std::string server = "127.0.0.1:" + std::to_string(freePort());
    // The daemon comes up a second after the command starts, as with `partitad ... &` typed
    // just before it.
    RunResult r =
        shell("(sleep 1; exec " + std::string(PARTITAD_PATH) + " --listen " + server + " --store " +
              q(dir / "store") + " --scene-root " + PARTITA_SCENES_DIR + " >" + q(dir / "log") +
              " 2>&1) & D=$!\n" + PARTITA_CLI_PATH + " --server " + server +
              " render cornell --width 16 --height 16 --spp 1 --detach; rc=$?\n"
              "kill $D; wait $D; exit $rc");
    EXPECT_EQ(r.exitCode, 0) << r.describe() << readText(dir / "log");
    EXPECT_EQ(lines(r.out).size(), 1u) << "the job id" << r.describe();
}

TEST(CliNewUser, ServerWithoutPortMeansTheDefaultPort) {
    // Needs the default port itself: skipped when something else has it.
    if (!portIsFree(50051)) GTEST_SKIP() << "port 50051 is taken";
    TempDir dir;
    RunResult r =
        shell(std::string(PARTITAD_PATH) + " --listen 127.0.0.1:50051 --store " + q(dir / "store") +
              " >" + q(dir / "log") + " 2>&1 & D=$!\n" + PARTITA_CLI_PATH +
              " --server localhost jobs; rc=$?\n" + "kill $D; wait $D; exit $rc");
    if (readText(dir / "log").find("cannot listen") != std::string::npos)
        GTEST_SKIP() << "port 50051 is taken";
    EXPECT_EQ(r.exitCode, 0) << r.describe() << readText(dir / "log");
    EXPECT_NE(r.out.find("ID"), std::string::npos) << r.describe();
}

TEST(CliNewUser, LimitsAreTheServersAndPrintAsNumbers) {
    Daemon daemon({"--max-spp", "100"});
    RunResult over = partita({"--server", daemon.address(), "render", "cornell", "--spp", "200"});
    expectOneLineError(over, "limit of 100 ");
    EXPECT_NE(over.err.find("RESOURCE_EXHAUSTED"), std::string::npos) << over.describe();
    RunResult huge =
        partita({"--server", daemon.address(), "render", "cornell", "--spp", "2000000"});
    expectOneLineError(huge, "2000000");
    EXPECT_EQ(huge.err.find("e+0"), std::string::npos) << huge.describe();
}

TEST(CliNewUser, WithoutATerminalProgressLinesAndAFinalState) {
    Daemon daemon;
    TempDir dir;
    RunResult r = partita({"--server", daemon.address(), "render", "cornell", "--width", "64",
                           "--height", "48", "--seconds", "2", "--out", (dir / "p.exr").string()});
    ASSERT_EQ(r.exitCode, 0) << r.describe();
    size_t progress = 0;
    for (const auto& line : r.errLines()) progress += line.rfind("render: ", 0) == 0;
    EXPECT_GE(progress, 2u) << "a first and a last progress line\n" << r.describe();
    EXPECT_NE(r.err.find(": done in "), std::string::npos) << r.describe();

    RunResult detached =
        partita(concat({"--server", daemon.address(), "render", "cornell", "--detach"}, kTiny));
    ASSERT_EQ(detached.exitCode, 0) << detached.describe();
    const std::string id = lines(detached.out).at(0);
    RunResult watched = partita({"--server", daemon.address(), "watch", id});
    ASSERT_EQ(watched.exitCode, 0) << watched.describe();
    EXPECT_NE(watched.err.find("job " + id + ": done in "), std::string::npos)
        << watched.describe();
}

TEST(CliNewUser, CtrlCDuringRenderCancelsTheJob) {
    Daemon daemon;
    TempDir dir;
    const std::string cli = PARTITA_CLI_PATH, s = " --server " + daemon.address();
    // Job control on, so that the background render takes SIGINT like a foreground one. A large
    // image: its render takes a moment to stop, so a CLI that returns at once is caught.
    RunResult r =
        shell("set -m\n" + cli + s + " render cornell --width 64 --height 48 --seconds 60 --out " +
              q(dir / "x.exr") +
              " 2>/dev/null & P=$!\n"
              "for i in $(seq 200); do " +
              cli + s +
              " jobs | grep -q rendering && break; sleep 0.1; done\n"
              "kill -INT $P; wait $P; echo \"exit $?\"\n" +
              cli + s + " jobs");
    ASSERT_NE(r.out.find("exit 130"), std::string::npos) << r.describe();
    EXPECT_EQ(r.out.find("rendering"), std::string::npos)
        << "right after Ctrl-C the job is no longer rendering\n"
        << r.describe();
    EXPECT_NE(r.out.find("cancelled"), std::string::npos) << r.describe();
}

TEST(CliNewUser, UploadedSceneKeepsItsFileName) {
    Daemon daemon;
    TempDir dir;
    RunResult r = partita(concat(
        {"--server", daemon.address(), "render", kCornell, "--out", (dir / "f.exr").string()},
        kTiny));
    ASSERT_EQ(r.exitCode, 0) << r.describe();
    auto meta = nlohmann::json::parse(readText(dir / "f.json"));
    EXPECT_EQ(meta["scene"], "cornell.gltf");
}

TEST(CliNewUser, SweepOverAParameterTheAlgorithmIgnoresIsRefused) {
    Daemon daemon;
    TempDir dir;
    RunResult r =
        partita(concat({"--server", daemon.address(), "sweep", "cornell", "--sweep", "y=8,32",
                        "--sweep", "radius=5,10", "--out-dir", (dir / "s").string()},
                       kTiny));
    expectOneLineError(r, "ignores y");
    RunResult help = partita({"render", "--help"});
    EXPECT_NE(help.out.find("pt"), std::string::npos);
    EXPECT_NE(help.out.find("guided"), std::string::npos)
        << "render --help lists every algorithm this build has\n"
        << help.out;
}

TEST(CliNewUser, SweepWithAReferenceOfAnotherSizeFailsClearly) {
    Daemon daemon;
    TempDir dir;
    RunResult ref = partita({"--server", daemon.address(), "render", "cornell", "--width", "16",
                             "--height", "12", "--spp", "1", "--out", (dir / "ref.exr").string()});
    ASSERT_EQ(ref.exitCode, 0) << ref.describe();
    RunResult r = partita(
        concat({"--server", daemon.address(), "sweep", "cornell", "--sweep", "spp=1,2",
                "--reference", (dir / "ref.exr").string(), "--out-dir", (dir / "s").string()},
               {"--width", "32", "--height", "24"}));
    expectOneLineError(r, "16x12");
    EXPECT_NE(r.err.find("32x24"), std::string::npos) << r.describe();
}

}  // namespace
}  // namespace partita::test
