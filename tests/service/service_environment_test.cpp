// The environment through the daemon: a uniform environment colour lights an uploaded scene that
// has no light of its own; without one the job says so in its note and metadata; a malformed
// colour is INVALID_ARGUMENT.
#include <gtest/gtest.h>

#include <cstring>
#include <nlohmann/json.hpp>

#include "image_io.h"
#include "in_process.h"
#include "service_client.h"

namespace partita::test {
namespace {

/// One triangle and nothing that emits (gltfWithBufferUri's scene, its buffer uploaded).
pb::JobSpec unlitTriangle() {
    std::string triangle(36, '\0');
    float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    std::memcpy(triangle.data(), v, 36);
    pb::JobSpec spec;
    spec.mutable_scene()->mutable_gltf()->set_gltf(gltfWithBufferUri("triangle.bin"));
    auto* r = spec.mutable_scene()->mutable_gltf()->add_resources();
    r->set_uri("triangle.bin");
    r->set_data(triangle);
    spec.set_width(16);
    spec.set_height(12);
    spec.mutable_budget()->set_kind(pb::BUDGET_KIND_SAMPLES_PER_PIXEL);
    spec.mutable_budget()->set_amount(2);
    return spec;
}

pb::Job runToEnd(pb::Partita::Stub& stub, const pb::JobSpec& spec, std::string& id) {
    Submitted job = submit(stub, spec);
    EXPECT_TRUE(job.status.ok()) << job.status.error_message();
    id = job.id;
    return waitForEnd(stub, job.id);
}

double meanOfResult(pb::Partita::Stub& stub, const std::string& id) {
    Fetched exr = fetch(stub, id, pb::RESULT_KIND_EXR);
    EXPECT_TRUE(exr.status.ok()) << exr.status.error_message();
    return luminance(readExrBytes(exr.bytes).combined.mean());
}

TEST(ServiceEnvironment, AColourLightsASceneWithoutLightsAndItsAbsenceIsANote) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    std::string dark, lit;
    pb::Job darkEnd = runToEnd(*stub, unlitTriangle(), dark);
    ASSERT_EQ(darkEnd.state(), pb::JOB_STATE_DONE) << darkEnd.error();
    EXPECT_NE(darkEnd.note().find("no light"), std::string::npos) << darkEnd.note();
    EXPECT_EQ(meanOfResult(*stub, dark), 0.0);
    Fetched meta = fetch(*stub, dark, pb::RESULT_KIND_METADATA);
    ASSERT_TRUE(meta.status.ok());
    EXPECT_NE(nlohmann::json::parse(meta.bytes)["labels"].value("warning", ""), "");

    pb::JobSpec spec = unlitTriangle();
    for (float c : {0.5f, 1.0f, 2.0f}) spec.add_environment_color(c);
    spec.set_environment_rotation_degrees(30);
    pb::Job litEnd = runToEnd(*stub, spec, lit);
    ASSERT_EQ(litEnd.state(), pb::JOB_STATE_DONE) << litEnd.error();
    EXPECT_EQ(litEnd.note(), "");
    EXPECT_GT(meanOfResult(*stub, lit), 0.5);  // mostly sky of luminance ~1.1
    Fetched litMeta = fetch(*stub, lit, pb::RESULT_KIND_METADATA);
    auto params = nlohmann::json::parse(litMeta.bytes)["parameters"];
    EXPECT_EQ(params["environment_color"].size(), 3u);
    EXPECT_EQ(params["environment_rotation"], 30.0);
}

/// An equirectangular EXR of one colour, as bytes.
std::string skyExr(Rgb colour) {
    TempDir dir;
    LayeredImage sky;
    sky.combined = Image(8, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) sky.combined.set(x, y, colour);
    writeExr(dir / "sky.exr", sky, {});
    return readFile(dir / "sky.exr");
}

TEST(ServiceEnvironment, AnImageUploadedWithTheSceneLightsIt) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::JobSpec spec = unlitTriangle();
    auto* r = spec.mutable_scene()->mutable_gltf()->add_resources();
    r->set_uri("sky.exr");
    r->set_data(skyExr(Rgb(2.0f)));
    spec.set_environment_file("sky.exr");
    std::string id;
    pb::Job end = runToEnd(*stub, spec, id);
    ASSERT_EQ(end.state(), pb::JOB_STATE_DONE) << end.error();
    EXPECT_EQ(end.note(), "");
    EXPECT_GT(meanOfResult(*stub, id), 1.0);  // mostly sky of radiance 2
    EXPECT_FALSE(fs::exists(store.path() / "jobs" / id / "environment.exr"))
        << "the image is not left in the store";
}

TEST(ServiceEnvironment, AnImageInTheNamedScenesFolderLightsIt) {
    // A named scene's job has no folder of its own before it runs; the image read from the
    // scene's folder must still reach OpenImageIO (issue #25 5: it always failed).
    TempDir store, root;
    fs::copy(fs::path(PARTITA_SCENES_DIR) / "cornell", root / "cornell",
             fs::copy_options::recursive);
    writeFile(root / "cornell" / "sky.exr", skyExr(Rgb(2.0f)));
    Daemon daemon(store.path(), {}, root.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    std::string dark, lit;
    ASSERT_EQ(runToEnd(*stub, sceneSpec("cornell", 8, 8, 2, 1), dark).state(), pb::JOB_STATE_DONE);
    pb::JobSpec spec = sceneSpec("cornell", 8, 8, 2, 1);
    spec.set_environment_file("sky.exr");
    pb::Job end = runToEnd(*stub, spec, lit);
    ASSERT_EQ(end.state(), pb::JOB_STATE_DONE) << end.error();
    // The box is closed: the sky adds no light, but it is a light the path tracer samples, so
    // the same seed gives another image (the same one would mean the sky was left out).
    Fetched darkExr = fetch(*stub, dark, pb::RESULT_KIND_EXR),
            litExr = fetch(*stub, lit, pb::RESULT_KIND_EXR);
    ASSERT_TRUE(darkExr.status.ok() && litExr.status.ok());
    EXPECT_NE(readExrBytes(litExr.bytes).combined.rgb, readExrBytes(darkExr.bytes).combined.rgb)
        << "the sky is one of the scene's lights";
    EXPECT_FALSE(fs::exists(store.path() / "jobs" / lit / "environment.exr"))
        << "the image is not left in the store";
}

/// A Radiance HDR file's header claiming `width` x `height` pixels, and no pixels: all that a
/// daemon should read of it before deciding whether it may decode it.
std::string hdrHeaderOnly(int width, int height) {
    return "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(height) + " +X " +
           std::to_string(width) + "\n";
}

TEST(ServiceEnvironment, AnImageIsAdmittedByItsHeaderBeforeItIsDecoded) {
    // issue #25 3: an environment image was decoded before its size was checked, and its
    // memory was not in the job's estimate.
    TempDir store;
    Daemon daemon(store.path(), {"--max-job-memory", "300"});
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    auto withImage = [](const std::string& bytes) {
        pb::JobSpec spec = unlitTriangle();
        auto* r = spec.mutable_scene()->mutable_gltf()->add_resources();
        r->set_uri("sky.hdr");
        r->set_data(bytes);
        spec.set_environment_file("sky.hdr");
        return spec;
    };
    Submitted huge = submit(*stub, withImage(hdrHeaderOnly(16385, 8192)));
    EXPECT_EQ(huge.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_EQ(huge.status.error_message(),
              "the environment image 'sky.hdr' is 16385 x 8192 pixels, more than the 16384 x "
              "8192 allowed");
    // 8192 x 4096 is allowed, but its 1 GiB while it loads is over this daemon's 300 MiB.
    Submitted big = submit(*stub, withImage(hdrHeaderOnly(8192, 4096)));
    EXPECT_EQ(big.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_NE(big.status.error_message().find("environment 1.0 GiB"), std::string::npos)
        << big.status.error_message();
    // A small one is admitted; its pixels are missing, and the job's error names the image as
    // the job gave it, not the store's copy of it.
    std::string id;
    pb::Job end = runToEnd(*stub, withImage(hdrHeaderOnly(64, 32)), id);
    EXPECT_EQ(end.state(), pb::JOB_STATE_FAILED);
    EXPECT_NE(end.error().find("sky.hdr"), std::string::npos) << end.error();
    EXPECT_EQ(end.error().find(store.path().string()), std::string::npos) << end.error();
}

TEST(ServiceEnvironment, AnImageMustBeUploadedOrInTheNamedScenesFolder) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    std::string id;
    pb::JobSpec missing = unlitTriangle();
    missing.set_environment_file("sky.exr");  // named but not uploaded
    pb::Job end = runToEnd(*stub, missing, id);
    EXPECT_EQ(end.state(), pb::JOB_STATE_FAILED);
    EXPECT_NE(end.error().find("no resource"), std::string::npos) << end.error();
    for (const std::string uri : {"../../../etc/passwd.exr", "/etc/x.exr", "../pool/x.hdr"}) {
        pb::JobSpec named = sceneSpec("cornell", 8, 8, 1, 1);
        named.set_environment_file(uri);
        pb::Job e = runToEnd(*stub, named, id);
        EXPECT_EQ(e.state(), pb::JOB_STATE_FAILED) << uri;
        EXPECT_NE(e.error().find("environment"), std::string::npos) << e.error();
    }
    pb::JobSpec png = unlitTriangle();
    png.set_environment_file("sky.png");
    EXPECT_EQ(submit(*stub, png).status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    pb::JobSpec both = unlitTriangle();
    both.set_environment_file("sky.exr");
    for (float c : {1.0f, 1.0f, 1.0f}) both.add_environment_color(c);
    EXPECT_EQ(submit(*stub, both).status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
}

TEST(ServiceEnvironment, AColourOfOtherThanThreeValuesIsInvalid) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::JobSpec spec = unlitTriangle();
    spec.add_environment_color(1);
    spec.add_environment_color(1);
    Submitted job = submit(*stub, spec);
    EXPECT_EQ(job.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_NE(job.status.error_message().find("environment_color"), std::string::npos);
    spec.add_environment_color(-1);
    job = submit(*stub, spec);
    EXPECT_EQ(job.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
}

}  // namespace
}  // namespace partita::test
