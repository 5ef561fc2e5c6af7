// partita render: through a private daemon (no --server) and through a running one.
#include <nlohmann/json.hpp>

#include "cli_test_util.h"
#include "image_io.h"

#include <grpcpp/grpcpp.h>

#include <cstring>
#include <thread>

#include "cli/proto.h"

namespace partita::test {
namespace {

namespace fs = std::filesystem;

void expectResults(const fs::path& exr, int width, int height) {
    ASSERT_TRUE(fs::exists(exr)) << exr;
    EXPECT_TRUE(fs::exists(fs::path(exr).replace_extension(".png")));
    const fs::path json = fs::path(exr).replace_extension(".json");
    ASSERT_TRUE(fs::exists(json));
    auto meta = nlohmann::json::parse(readText(json));
    EXPECT_TRUE(meta.is_object());
    LayeredImage image = readExr(exr);
    EXPECT_EQ(image.combined.width, width);
    EXPECT_EQ(image.combined.height, height);
    EXPECT_GT(image.combined.mean().x + image.combined.mean().y + image.combined.mean().z, 0.0f);
}

TEST(CliRender, PrivateDaemonRendersUploadedGltfAndCleansUp) {
    TempDir dir;
    fs::create_directory(dir / "tmp");
    // No --server: partita finds partitad next to itself (../server/partitad) and uses TMPDIR
    // for the daemon's store, which must be gone afterwards.
    RunResult r = partita(concat({"render", kCornell, "--out", (dir / "a.exr").string(),
                                  "--previews", (dir / "previews").string()},
                                 kTiny),
                          {{"TMPDIR", (dir / "tmp").string()}});
    ASSERT_EQ(r.exitCode, 0) << r.describe();
    expectResults(dir / "a.exr", 32, 24);
    EXPECT_TRUE(fs::exists(dir / "previews" / "combined.png")) << r.describe();
    EXPECT_TRUE(fs::is_empty(dir / "tmp")) << "the private daemon's folder was left behind";
}

TEST(CliRender, AnEnvironmentImageTravelsWithAnUploadedScene) {
    TempDir dir;
    // One triangle, nothing that emits.
    std::string triangle(36, '\0');
    float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    std::memcpy(triangle.data(), v, 36);
    writeText(dir / "tri.bin", triangle);
    nlohmann::json j = {{"asset", {{"version", "2.0"}}},
                        {"scene", 0},
                        {"scenes", {{{"nodes", {0}}}}},
                        {"nodes", {{{"mesh", 0}}}},
                        {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}}},
                        {"buffers", {{{"uri", "tri.bin"}, {"byteLength", 36}}}},
                        {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}}}},
                        {"accessors",
                         {{{"bufferView", 0},
                           {"componentType", 5126},
                           {"count", 3},
                           {"type", "VEC3"},
                           {"min", {0, 0, 0}},
                           {"max", {1, 1, 0}}}}}};
    writeText(dir / "tri.gltf", j.dump());
    LayeredImage sky;
    sky.combined = Image(8, 4);
    for (float& c : sky.combined.rgb) c = 2.0f;
    writeExr(dir / "sky.exr", sky, {});
    RunResult r = partita(concat({"-q", "render", (dir / "tri.gltf").string(), "--environment",
                                  (dir / "sky.exr").string(), "--out", (dir / "e.exr").string()},
                                 kTiny));
    ASSERT_EQ(r.exitCode, 0) << r.describe();
    EXPECT_GT(luminance(readExr(dir / "e.exr").combined.mean()), 1.0f);
    auto meta = nlohmann::json::parse(readText(dir / "e.json"));
    EXPECT_EQ(meta["parameters"]["environment"], "partita-environment/sky.exr");
}

TEST(CliRender, PrivateDaemonRendersSceneByName) {
    TempDir dir;
    RunResult r =
        partita(concat({"-q", "render", "cornell", "--out", (dir / "n.exr").string()}, kTiny));
    ASSERT_EQ(r.exitCode, 0) << r.describe();
    EXPECT_TRUE(r.err.empty()) << "-q prints nothing on success\n" << r.describe();
    expectResults(dir / "n.exr", 32, 24);
}

TEST(CliRender, WithServerByNameAndUpload) {
    Daemon daemon;
    TempDir dir;
    RunResult byName =
        partita(concat({"--server", daemon.address(), "render", "cornell", "--out",
                        (dir / "name.exr").string(), "--previews", (dir / "prev").string()},
                       kTiny));
    ASSERT_EQ(byName.exitCode, 0) << byName.describe() << daemon.log();
    expectResults(dir / "name.exr", 32, 24);
    EXPECT_TRUE(fs::exists(dir / "prev" / "combined.png"));

    // Global options may also follow the subcommand.
    RunResult upload = partita(concat({"render", kCornell, "--server", daemon.address(), "--out",
                                       (dir / "up.exr").string(), "--seed", "7"},
                                      kTiny));
    ASSERT_EQ(upload.exitCode, 0) << upload.describe() << daemon.log();
    expectResults(dir / "up.exr", 32, 24);
    auto meta = nlohmann::json::parse(readText(dir / "up.json"));
    EXPECT_EQ(meta.dump().find("\"seed\":7") != std::string::npos, true) << meta.dump();
}

TEST(CliRender, AnUploadWaitsWhileTheServerReceivesAsManyAsItTakes) {
    Daemon daemon({"--max-upload-streams", "1"});
    // A stream that sent its header and half its bytes holds the server's one upload place.
    auto stub = partita::v1::Partita::NewStub(
        grpc::CreateChannel(daemon.address(), grpc::InsecureChannelCredentials()));
    grpc::ClientContext context;
    partita::v1::UploadSceneResponse response;
    auto held = stub->UploadScene(&context, &response);
    partita::v1::UploadChunk chunk;
    chunk.mutable_header()->set_format(partita::v1::SCENE_FORMAT_GLB);
    chunk.mutable_header()->set_scene_bytes(10);
    chunk.set_data("01234");
    ASSERT_TRUE(held->Write(chunk));
    // Admitted once its file is in the store.
    auto staged = [&] {
        std::error_code ec;
        auto it = fs::directory_iterator(daemon.store() / "uploads", ec);
        return !ec && it != fs::directory_iterator();
    };
    for (int i = 0; i < 400 && !staged(); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(25));
    ASSERT_TRUE(staged());
    std::thread release([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(1500));
        partita::v1::UploadChunk rest;
        rest.set_data("56789");
        held->Write(rest);
        held->WritesDone();
        held->Finish();
    });
    TempDir dir;
    RunResult r = partita(concat(
        {"--server", daemon.address(), "render", kCornell, "--out", (dir / "up.exr").string()},
        kTiny));
    release.join();
    ASSERT_EQ(r.exitCode, 0) << r.describe() << daemon.log();
    EXPECT_NE(r.err.find("waiting to send the scene"), std::string::npos) << r.err;
    expectResults(dir / "up.exr", 32, 24);
}

TEST(CliRender, DetachThenWatchThenGet) {
    Daemon daemon;
    TempDir dir;
    RunResult submit = partita(concat(
        {"--server", daemon.address(), "render", kCornell, "--detach", "--label", "detached"},
        kTiny));
    ASSERT_EQ(submit.exitCode, 0) << submit.describe();
    auto out = lines(submit.out);
    ASSERT_EQ(out.size(), 1u) << submit.describe();
    const std::string id = out[0];
    EXPECT_EQ(words(id).size(), 1u);

    RunResult watch =
        partita({"--server", daemon.address(), "watch", id, "--previews", (dir / "prev").string()});
    ASSERT_EQ(watch.exitCode, 0) << watch.describe();

    RunResult get =
        partita({"--server", daemon.address(), "get", id, "--out", (dir / "g.exr").string()});
    ASSERT_EQ(get.exitCode, 0) << get.describe();
    expectResults(dir / "g.exr", 32, 24);

    // The job is listed, done, with its label and algorithm.
    RunResult jobs = partita({"--server", daemon.address(), "jobs"});
    ASSERT_EQ(jobs.exitCode, 0) << jobs.describe();
    auto rows = lines(jobs.out);
    ASSERT_GE(rows.size(), 2u) << jobs.describe();
    auto header = words(rows[0]);
    EXPECT_EQ(header,
              (std::vector<std::string>{"ID", "STATE", "ALGORITHM", "SCENE", "LABEL", "PROGRESS"}));
    bool found = false;
    for (size_t i = 1; i < rows.size(); ++i) {
        auto w = words(rows[i]);
        if (!w.empty() && w[0] == id) {
            found = true;
            EXPECT_EQ(
                w, (std::vector<std::string>{id, "done", "pt", "cornell.gltf", "detached", "100%"}))
                << "an uploaded file is listed by its file name";
        }
    }
    EXPECT_TRUE(found) << jobs.describe();
}

/// The plain progress line (no terminal) of `phase` that says 100%, or "".
std::string finalProgressLine(const RunResult& r, const std::string& phase) {
    for (const auto& line : r.errLines())
        if (line.rfind(phase + ": 100.0%", 0) == 0) return line;
    return "";
}

TEST(CliRender, MltRendersEndToEndAndPrintsItsAcceptance) {
    TempDir dir;
    const std::vector<std::string> mlt = {"--algorithm", "mlt", "--mpp",    "4",
                                          "--width",     "16",  "--height", "12"};
    // Through a private daemon, without a terminal: plain progress lines, the last one of the
    // chains with the rate, the ETA and the acceptance per mutation type.
    RunResult r = partita(concat({"render", "cornell", "--out", (dir / "m.exr").string()}, mlt));
    ASSERT_EQ(r.exitCode, 0) << r.describe();
    std::string render = finalProgressLine(r, "render");
    ASSERT_FALSE(render.empty()) << r.describe();
    EXPECT_NE(render.find("mutations/s  ETA "), std::string::npos) << render;
    EXPECT_NE(render.find("  acc bidir 0."), std::string::npos) << render;
    EXPECT_NE(render.find(" lens 0."), std::string::npos) << render;
    EXPECT_NE(r.err.find("bootstrap: "), std::string::npos) << "the bootstrap's progress\n"
                                                            << r.describe();
    expectResults(dir / "m.exr", 16, 12);
    EXPECT_GT(readExr(dir / "m.exr").layers.size(), 1u) << "per-type layers";
    auto meta = nlohmann::json::parse(readText(dir / "m.json"));
    EXPECT_EQ(meta["algorithm"], "mlt");
    EXPECT_TRUE(meta["stats"].contains("acceptance_bidirectional")) << meta["stats"].dump();
    EXPECT_GT(meta["stats"]["b"].get<double>(), 0);

    // watch shows the same of a detached job (of 5 s, so that the watch joins while it runs,
    // even on a busy machine).
    Daemon daemon;
    RunResult submit =
        partita({"--server", daemon.address(), "render", "cornell", "--detach", "--algorithm",
                 "mlt", "--seconds", "5", "--width", "16", "--height", "12"});
    ASSERT_EQ(submit.exitCode, 0) << submit.describe();
    RunResult watch = partita({"--server", daemon.address(), "watch", lines(submit.out).at(0)});
    ASSERT_EQ(watch.exitCode, 0) << watch.describe();
    EXPECT_NE(finalProgressLine(watch, "render").find("  acc bidir 0."), std::string::npos)
        << watch.describe();

    // --spp is not mlt's budget: the server's one-line refusal, before anything renders.
    expectOneLineError(
        partita({"--server", daemon.address(), "render", "cornell", "--algorithm", "mlt", "--spp",
                 "4", "--width", "16", "--height", "12"}),
        "algorithm 'mlt' takes its budget in mutations per pixel or seconds, not samples per "
        "pixel (INVALID_ARGUMENT)");
}

TEST(CliRender, PartitionedRendersEndToEndAndWatchShowsThePartitionTable) {
    TempDir dir;
    // The estimators chosen (the pilots' phase between the pre-pass and the render, whose
    // per-pixel samples carry the table too): every phase and the table still show.
    const std::vector<std::string> part = {"--algorithm", "partitioned", "--mpp",        "16",
                                           "--width",     "16",          "--height",     "12",
                                           "--k",         "3",           "--bootstrap",  "4000",
                                           "--prepass",   "pt",          "--estimators", "auto"};
    RunResult r =
        partita(concat({"render", "cornell-glass", "--out", (dir / "p.exr").string()}, part));
    ASSERT_EQ(r.exitCode, 0) << r.describe();
    EXPECT_NE(r.err.find("prepass: "), std::string::npos) << "the pre-pass's progress\n"
                                                          << r.describe();
    std::string render = finalProgressLine(r, "render");
    ASSERT_FALSE(render.empty()) << r.describe();
    // The partition table follows the last plain progress line: a header, then one row per
    // partition (type, P(i), b_i, acceptance), the complement last.
    EXPECT_NE(r.err.find("  partition "), std::string::npos) << r.describe();
    EXPECT_NE(r.err.find("P(i)"), std::string::npos) << r.describe();
    EXPECT_NE(r.err.find("\n  complement "), std::string::npos) << r.describe();
    expectResults(dir / "p.exr", 16, 12);
    LayeredImage image = readExr(dir / "p.exr");
    ASSERT_GE(image.layers.size(), 2u) << "one layer per partition";
    EXPECT_EQ(image.layers.back().name, "complement");
    auto meta = nlohmann::json::parse(readText(dir / "p.json"));
    EXPECT_EQ(meta["algorithm"], "partitioned");
    EXPECT_EQ(meta["parameters"]["prepass"], "pt");
    EXPECT_EQ(meta["parameters"]["bootstrap"], 4000);
    EXPECT_EQ(meta["stats"]["prepass_samples"], 4000.0);
    EXPECT_EQ(meta["labels"]["partition_0_type"], image.layers.front().name);

    // watch shows the table of a detached job (of 6 s, so that the watch joins while it runs,
    // even on a loaded machine).
    Daemon daemon;
    RunResult submit = partita({"--server", daemon.address(), "render", "cornell-glass", "--detach",
                                "--algorithm", "partitioned", "--seconds", "6", "--width", "16",
                                "--height", "12", "--bootstrap", "4000"});
    ASSERT_EQ(submit.exitCode, 0) << submit.describe();
    RunResult watch = partita({"--server", daemon.address(), "watch", lines(submit.out).at(0)});
    ASSERT_EQ(watch.exitCode, 0) << watch.describe();
    EXPECT_FALSE(finalProgressLine(watch, "render").empty()) << watch.describe();
    EXPECT_NE(watch.err.find("  partition "), std::string::npos) << watch.describe();
    EXPECT_NE(watch.err.find("\n  complement "), std::string::npos) << watch.describe();

    // A pre-pass the service does not know: its one-line refusal.
    expectOneLineError(
        partita({"--server", daemon.address(), "render", "cornell", "--algorithm", "partitioned",
                 "--prepass", "magic", "--width", "16", "--height", "12"}),
        "prepass 'magic' is not one of auto | pt | bdpt");
}

TEST(CliRender, CancelARunningJob) {
    Daemon daemon;
    RunResult submit = partita({"--server", daemon.address(), "render", "cornell", "--detach",
                                "--seconds", "60", "--width", "32", "--height", "24"});
    ASSERT_EQ(submit.exitCode, 0) << submit.describe();
    const std::string id = lines(submit.out).at(0);

    RunResult cancel = partita({"--server", daemon.address(), "cancel", id});
    ASSERT_EQ(cancel.exitCode, 0) << cancel.describe() << daemon.log();
    EXPECT_EQ(lines(cancel.out).at(0), "job " + id + ": cancelled") << cancel.describe();

    // Watching a cancelled job ends at once, and fails: it did not finish.
    RunResult watch = partita({"--server", daemon.address(), "watch", id});
    expectOneLineError(watch, "was cancelled");

    RunResult get = partita({"--server", daemon.address(), "get", id});
    expectOneLineError(get, "(FAILED_PRECONDITION)");

    RunResult jobs = partita({"--server", daemon.address(), "jobs"});
    ASSERT_EQ(jobs.exitCode, 0);
    EXPECT_NE(jobs.out.find("cancelled"), std::string::npos) << jobs.describe();
}

TEST(CliRender, TokenIsSentFromTokenFile) {
    TempDir dir;
    { std::ofstream(dir / "token") << "s3cret-token\n"; }
    Daemon daemon({"--token-file", (dir / "token").string()});
    RunResult without = partita({"--server", daemon.address(), "jobs"});
    expectOneLineError(without, "(UNAUTHENTICATED)");
    RunResult with =
        partita({"--server", daemon.address(), "--token-file", (dir / "token").string(), "jobs"});
    EXPECT_EQ(with.exitCode, 0) << with.describe();
    RunResult probe = runProgram({PARTITA_PROBE_PATH, "--server", daemon.address(), "--token-file",
                                  (dir / "token").string()});
    EXPECT_EQ(probe.exitCode, 0) << probe.describe();
}

TEST(CliRender, TlsWithCaFile) {
    TempDir dir;
    const std::string cmd =
        "openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj /CN=partita "
        "-addext subjectAltName=DNS:localhost,IP:127.0.0.1 -keyout '" +
        (dir / "key.pem").string() + "' -out '" + (dir / "cert.pem").string() + "' >/dev/null 2>&1";
    if (std::system(cmd.c_str()) != 0) GTEST_SKIP() << "no openssl to make a test certificate";
    { std::ofstream(dir / "token") << "tls-token\n"; }
    Daemon daemon({"--tls-cert", (dir / "cert.pem").string(), "--tls-key",
                   (dir / "key.pem").string(), "--token-file", (dir / "token").string()});
    const std::vector<std::string> secure = {"--server",     daemon.address(),
                                             "--tls-ca",     (dir / "cert.pem").string(),
                                             "--token-file", (dir / "token").string()};
    RunResult r = partita(concat(
        secure, concat({"-q", "render", "cornell", "--out", (dir / "t.exr").string()}, kTiny)));
    ASSERT_EQ(r.exitCode, 0) << r.describe() << daemon.log();
    EXPECT_TRUE(fs::exists(dir / "t.exr"));
    // Plain text to a TLS server fails in one line that hints at --tls-ca.
    expectOneLineError(partita({"--server", daemon.address(), "jobs"}), "--tls-ca");
    RunResult probe = runProgram({PARTITA_PROBE_PATH, "--server", daemon.address(), "--tls-ca",
                                  (dir / "cert.pem").string(), "--tls-server-name", "localhost"});
    EXPECT_EQ(probe.exitCode, 0) << probe.describe();
}

TEST(CliRender, HealthProbe) {
    Daemon daemon;
    RunResult ok = runProgram({PARTITA_PROBE_PATH, "--server", daemon.address()});
    EXPECT_EQ(ok.exitCode, 0) << ok.describe();
    RunResult down = runProgram({PARTITA_PROBE_PATH, "--server", "127.0.0.1:1", "--timeout", "2"});
    EXPECT_EQ(down.exitCode, 1) << down.describe();
    EXPECT_EQ(down.errLines().size(), 1u) << down.describe();
}

}  // namespace
}  // namespace partita::test
