// The CLI's pieces without a server: sweep axes, uri decoding, metrics, tables.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "cli/connection.h"
#include "cli/errors.h"
#include "cli/image_files.h"
#include "cli/job_spec.h"
#include "cli/scene_source.h"
#include "cli/sweep_axis.h"
#include "cli/table.h"
#include "image_io.h"
#include "image_metrics.h"
#include "process.h"

namespace partita::cli {
namespace {

TEST(SweepAxis, ParsesAndApplies) {
    SweepAxis a = parseSweepAxis("max_depth=1,2,8", "guided");
    EXPECT_EQ(a.name, "max-depth");
    EXPECT_EQ(a.values, (std::vector<std::string>{"1", "2", "8"}));
    partita::v1::JobSpec spec;
    applySweepValue(spec, "max-depth", "8");
    applySweepValue(spec, "radius", "2.5");
    applySweepValue(spec, "mpp", "32");
    applySweepValue(spec, "seed", "18446744073709551615");
    // Parameters travel by their canonical name, as the text the server reads.
    EXPECT_EQ(spec.parameters().at("max_depth").text_value(), "8");
    EXPECT_EQ(spec.parameters().at("radius").text_value(), "2.5");
    EXPECT_EQ(spec.budget().kind(), partita::v1::BUDGET_KIND_MUTATIONS_PER_PIXEL);
    EXPECT_EQ(spec.budget().amount(), 32);
    EXPECT_EQ(spec.parameters().at("seed").text_value(), "18446744073709551615");
    // Each value is read with the parameter's declaration.
    EXPECT_THROW(parseSweepAxis("y=1.5", "guided"), CliError);
    EXPECT_THROW(parseSweepAxis("seed=-1", "guided"), CliError);
    EXPECT_THROW(parseSweepAxis("radius=inf", "guided"), CliError);
    EXPECT_THROW(parseSweepAxis("radius=0", "guided"), CliError);
    EXPECT_THROW(parseSweepAxis("y=1,1", "guided"), CliError);
    EXPECT_THROW(parseSweepAxis("=1", "guided"), CliError);
    EXPECT_THROW(parseSweepAxis("y=99999999999", "guided"), CliError);
    // Names the server checks against the algorithm's declarations (sweep_command.cpp), with
    // what a sweep over them would do; values of a name this build does not know go unchecked.
    EXPECT_NO_THROW(parseSweepAxis("radius=1,2", "pt"));
    EXPECT_NO_THROW(parseSweepAxis("strength=1,2", "server-only"));
}

TEST(SceneSource, PercentDecodingAndClassification) {
    EXPECT_EQ(percentDecode("my%20file.bin"), "my file.bin");
    EXPECT_EQ(percentDecode("a%2Fb"), "a/b");
    EXPECT_THROW(percentDecode("bad%2"), CliError);
    EXPECT_THROW(percentDecode("bad%zz"), CliError);
    EXPECT_TRUE(classifyScene("x/scene.GLTF").isFile);
    EXPECT_TRUE(classifyScene("scene.glb").isFile);
    EXPECT_FALSE(classifyScene("cornell").isFile);
    EXPECT_EQ(sceneStem(classifyScene("a/b/pool.gltf")), "pool");
}

TEST(ImageFiles, TheCoresReaderAndMetricsWithTheCLIsErrors) {
    Image a(2, 1), b(2, 1);
    b.rgb = {1, 1, 1, 0, 0, 0};
    a.rgb = {1, 1, 1, 0.1f, 0.1f, 0.1f};
    ErrorMetrics m = imageError(a, b);
    EXPECT_EQ(m.rmse, rmse(a, b));
    EXPECT_EQ(m.relMse, relMse(a, b));
    EXPECT_THROW(imageError(Image(2, 2), b), CliError);
    partita::test::TempDir dir;
    EXPECT_THROW(readResultExr(dir / "missing.exr"), CliError);
    std::ofstream(dir / "junk.exr") << "not an exr";
    try {
        readResultExr(dir / "junk.exr");
        ADD_FAILURE() << "junk read as an EXR";
    } catch (const CliError& e) {
        EXPECT_NE(std::string(e.what()).find("junk.exr"), std::string::npos) << e.what();
    }
}

TEST(Table, CsvQuotes) {
    Table t({"a", "b"});
    t.addRow({"x,y", "he said \"hi\""});
    EXPECT_EQ(t.csv(), "a,b\n\"x,y\",\"he said \"\"hi\"\"\"\n");
    EXPECT_EQ(formatNumber(0.25), "0.25");
}

TEST(JobSpec, ValidatesLikeTheCore) {
    partita::v1::JobSpec spec;
    spec.set_algorithm("guided");
    EXPECT_EQ(validateJobSpec(spec), "");
    setParameter(spec, "width", "0");
    EXPECT_EQ(validateJobSpec(spec), "width = 0 must be >= 1");
    setParameter(spec, "width", "8");
    setParameter(spec, "radius", "0");
    EXPECT_EQ(validateJobSpec(spec), "radius = 0 is outside (0, 4096] pixels");
    setParameter(spec, "radius", "5");
    EXPECT_EQ(validateJobSpec(spec), "");
    spec.set_algorithm("pt");
    EXPECT_EQ(validateJobSpec(spec).rfind("unknown parameter 'radius' for pt", 0), 0u);
    spec.mutable_parameters()->erase("radius");
    spec.mutable_budget()->set_kind(partita::v1::BUDGET_KIND_SAMPLES_PER_PIXEL);
    spec.mutable_budget()->set_amount(1.5);
    EXPECT_NE(validateJobSpec(spec).find("whole"), std::string::npos);
}

TEST(Connection, HostWithoutPortGetsTheDaemonsDefaultPort) {
    EXPECT_EQ(withDefaultPort("localhost"), "localhost:50051");
    EXPECT_EQ(withDefaultPort("127.0.0.1"), "127.0.0.1:50051");
    EXPECT_EQ(withDefaultPort("[::1]"), "[::1]:50051");
    EXPECT_EQ(withDefaultPort("::1"), "[::1]:50051");
    EXPECT_EQ(withDefaultPort("localhost:7"), "localhost:7");
    EXPECT_EQ(withDefaultPort("[::1]:7"), "[::1]:7");
    EXPECT_EQ(withDefaultPort("unix:/tmp/s"), "unix:/tmp/s");
}

// A minimal container has no "localhost" in /etc/hosts and no DNS server: the dialled target
// must not need a resolver.
TEST(Connection, LocalhostIsDialledAsTheIpv4Loopback) {
    EXPECT_EQ(loopbackForLocalhost("localhost:50051"), "127.0.0.1:50051");
    EXPECT_EQ(loopbackForLocalhost("localhost:7"), "127.0.0.1:7");
    EXPECT_EQ(loopbackForLocalhost("localhostx:7"), "localhostx:7");
    EXPECT_EQ(loopbackForLocalhost("render1.example:7"), "render1.example:7");
    EXPECT_EQ(loopbackForLocalhost("dns:localhost:7"), "dns:localhost:7");
}

TEST(Table, CountsPrintAsPlainNumbers) {
    EXPECT_EQ(formatCount(1048576), "1048576");
    EXPECT_EQ(formatCount(65536), "65536");
    EXPECT_EQ(formatCount(0.5), "0.5");
}

TEST(Errors, StatusCodesAndOneLine) {
    EXPECT_EQ(statusCodeName(grpc::StatusCode::INVALID_ARGUMENT), "INVALID_ARGUMENT");
    EXPECT_EQ(oneLine("a\nb  c\n"), "a b c");
    EXPECT_EQ(oneLine("x\x1b[2Jy"), "x?[2Jy") << "no terminal escapes from a server's message";
    try {
        throwStatus(grpc::Status(grpc::StatusCode::NOT_FOUND, "no job 'x'"), "watch job x");
        FAIL();
    } catch (const CliError& e) {
        EXPECT_STREQ(e.what(), "watch job x: no job 'x'");
        EXPECT_EQ(e.code(), "NOT_FOUND");
    }
}

}  // namespace
}  // namespace partita::cli
