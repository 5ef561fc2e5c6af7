// One parameter table (issue #21): a parameter declared once, in an algorithm that exists only
// in the tests (throwaway/), reaches the CLI's flags and --help, the daemon's validation and
// GetServerInfo, the job's metadata and EXR attributes, the reference key, the shard plan and a
// sweep; no file outside the tests names it.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli_test_util.h"
#include "eval/reference_key.h"
#include "frontend/render_options.h"
#include "image_io.h"
#include "params/job_parameters.h"
#include "shard/shard_files.h"
#include "throwaway/throwaway_algorithm.h"

namespace partita::test {
namespace {

namespace fs = std::filesystem;

constexpr const char* kAlgorithm = "test-constant";

/// The options of `args` after `partita render`'s flags parse them, finalised: "" or the error.
std::string parseRender(std::vector<std::string> args, RenderOptions& o) {
    CLI::App app;
    addRenderOptions(app, o, kAlgorithm);
    args.insert(args.begin(), "render");
    std::vector<const char*> argv;
    for (const auto& a : args) argv.push_back(a.c_str());
    try {
        app.parse(int(argv.size()), argv.data());
    } catch (const CLI::ParseError& e) {
        return e.what();
    }
    return finalizeRenderOptions(o);
}

TEST(Parameters, ATestAlgorithmsParameterReachesTheFlagsAndTheirHelp) {
    registerThrowawayAlgorithm();
    CLI::App app;
    RenderOptions o;
    addRenderOptions(app, o, kAlgorithm);
    std::string help = app.help();
    EXPECT_NE(help.find("--strength"), std::string::npos) << help;
    EXPECT_NE(help.find("radiance of every pixel [default 1; [0, 10]]"), std::string::npos) << help;
    EXPECT_NE(help.find("Parameters of test-constant"), std::string::npos) << help;
    EXPECT_EQ(help.find("--radius"), std::string::npos) << "guided's parameter is not shown";
    EXPECT_NE(help.find("--max-depth"), std::string::npos) << "the shared ones are";

    RenderOptions given;
    ASSERT_EQ(parseRender({"--algorithm", kAlgorithm, "--strength", "3"}, given), "");
    ASSERT_NE(given.settings.parameters.find("strength"), nullptr);
    EXPECT_EQ(std::get<double>(*given.settings.parameters.find("strength")), 3.0);
    RenderOptions generic;
    ASSERT_EQ(parseRender({"--algorithm", kAlgorithm, "--param", "strength=2.5"}, generic), "");
    ASSERT_NE(generic.settings.parameters.find("strength"), nullptr);
    EXPECT_EQ(std::get<double>(*generic.settings.parameters.find("strength")), 2.5);
    RenderOptions bad;
    EXPECT_EQ(parseRender({"--algorithm", kAlgorithm, "--strength", "11"}, bad),
              "strength = 11 is outside [0, 10]");
    RenderOptions foreign;
    EXPECT_NE(parseRender({"--algorithm", kAlgorithm, "--radius", "3"}, foreign)
                  .find("unknown parameter 'radius' for test-constant"),
              std::string::npos);
}

TEST(Parameters, ATestAlgorithmsParameterReachesTheReferenceKeyAndTheShardPlan) {
    registerThrowawayAlgorithm();
    auto key = [](std::optional<double> strength) {
        RenderSettings s;
        if (strength) s.parameters.set("strength", *strength);
        return eval::referenceKey(eval::sceneFiles(kCornell), kAlgorithm, s);
    };
    EXPECT_EQ(key(std::nullopt), key(1.0)) << "the default, written out or not, is one key";
    EXPECT_NE(key(3.0), key(4.0));
    EXPECT_NE(
        eval::referenceKeyText(eval::sceneFiles(kCornell), kAlgorithm, {}).find("strength=1\n"),
        std::string::npos);

    ShardPlan plan;
    plan.algorithm = kAlgorithm;
    plan.scene = kCornell;
    plan.settings.parameters.set("strength", 3.5);
    ShardPlan back = deserializeShardPlan(serializeShardPlan(plan));
    ASSERT_NE(back.settings.parameters.find("strength"), nullptr);
    EXPECT_EQ(std::get<double>(*back.settings.parameters.find("strength")), 3.5);
}

TEST(Parameters, ATestAlgorithmsParameterReachesTheDaemonTheMetadataAndASweep) {
    Daemon daemon({}, PARTITAD_THROWAWAY_PATH);
    TempDir dir;
    const std::vector<std::string> job = {"--algorithm", kAlgorithm, "--width", "8",
                                          "--height",    "6",        "--spp",   "1"};
    // The CLI of this build does not have the algorithm: --param carries the parameter, and
    // the daemon checks it.
    RunResult ok = partita(concat({"--server", daemon.address(), "render", "cornell", "--param",
                                   "strength=3", "--out", (dir / "c.exr").string()},
                                  job));
    ASSERT_EQ(ok.exitCode, 0) << ok.describe() << daemon.log();
    auto meta = nlohmann::json::parse(readText(dir / "c.json"));
    EXPECT_EQ(meta["parameters"]["strength"], 3.0);
    std::map<std::string, std::string> attributes;
    LayeredImage image = readExr(dir / "c.exr", &attributes);
    EXPECT_EQ(attributes["partita:strength"], "3");
    EXPECT_EQ(image.combined.rgb.at(0), 3.0f);

    RunResult outside =
        partita(concat({"--server", daemon.address(), "render", "cornell", "--param", "strength=11",
                        "--out", (dir / "d.exr").string()},
                       job));
    expectOneLineError(outside, "strength = 11 is outside [0, 10] (INVALID_ARGUMENT)");
    RunResult misspelled =
        partita(concat({"--server", daemon.address(), "render", "cornell", "--param", "strenght=1",
                        "--out", (dir / "d.exr").string()},
                       job));
    expectOneLineError(misspelled, "unknown parameter 'strenght' for test-constant");

    RunResult sweep = partita(concat({"--server", daemon.address(), "sweep", "cornell", "--sweep",
                                      "strength=1,2", "--out-dir", (dir / "sw").string()},
                                     job));
    ASSERT_EQ(sweep.exitCode, 0) << sweep.describe() << daemon.log();
    auto csv = lines(readText(dir / "sw" / "sweep.csv"));
    ASSERT_EQ(csv.size(), 3u);
    EXPECT_EQ(csv[0].rfind("strength,", 0), 0u) << csv[0];
    EXPECT_EQ(csv[1].rfind("1,", 0), 0u) << csv[1];
    EXPECT_EQ(csv[2].rfind("2,", 0), 0u) << csv[2];
    auto second = nlohmann::json::parse(readText(dir / "sw" / "strength=2.json"));
    EXPECT_EQ(second["parameters"]["strength"], 2.0);
    RunResult ignored = partita(
        concat({"--server", daemon.address(), "sweep", "cornell", "--sweep", "radius=1,2"}, job));
    expectOneLineError(ignored, "ignores radius");
}

}  // namespace
}  // namespace partita::test
