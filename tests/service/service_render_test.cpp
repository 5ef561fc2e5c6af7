// Rendering through the daemon: results equal the in-process render bit for bit, previews arrive
// and end with the result image, result files stream in chunks, uploads render like named scenes.
#include <grpcpp/generic/generic_stub.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "in_process.h"
#include "service_client.h"

namespace partita::test {
namespace {

using namespace std::chrono_literals;

const fs::path kScenes = PARTITA_SCENES_DIR;

TEST(ServiceRender, ResultEqualsInProcessRenderBitForBit) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::JobSpec spec = sceneSpec("cornell-glass", 40, 30, 8, 7);
    Submitted job = submit(*stub, spec);
    ASSERT_TRUE(job.status.ok()) << job.status.error_message();
    WatchLog log = watch(*stub, job.id);
    ASSERT_TRUE(log.status.ok()) << log.status.error_message();
    ASSERT_TRUE(log.last());
    ASSERT_EQ(log.last()->state(), pb::JOB_STATE_DONE) << log.last()->error();
    // The states in order: QUEUED (or later, on joining), LOADING, RENDERING, DONE.
    std::vector<pb::JobState> states = log.states();
    EXPECT_TRUE(std::is_sorted(states.begin(), states.end())) << "states went backwards";
    EXPECT_NE(std::find(states.begin(), states.end(), pb::JOB_STATE_RENDERING), states.end());

    Fetched exr = fetch(*stub, job.id, pb::RESULT_KIND_EXR);
    ASSERT_TRUE(exr.status.ok()) << exr.status.error_message();
    EXPECT_TRUE(exr.chunksConsistent);
    LayeredImage remote = readExrBytes(exr.bytes);
    LayeredImage local =
        renderInProcess(kScenes / "cornell-glass" / "cornell-glass.gltf", 40, 30, 8, 7);
    EXPECT_GT(local.layers.size(), 1u);
    EXPECT_EQ(compareImages(remote, local), "");
}

TEST(ServiceRender, BdptThroughTheDaemonEqualsInProcessBitForBit) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::JobSpec spec = sceneSpec("cornell-point", 32, 24, 4, 5);
    spec.set_algorithm("bdpt");
    Submitted job = submit(*stub, spec);
    ASSERT_TRUE(job.status.ok()) << job.status.error_message();
    WatchLog log = watch(*stub, job.id);
    ASSERT_TRUE(log.last());
    ASSERT_EQ(log.last()->state(), pb::JOB_STATE_DONE) << log.last()->error();
    Fetched exr = fetch(*stub, job.id, pb::RESULT_KIND_EXR);
    ASSERT_TRUE(exr.status.ok()) << exr.status.error_message();
    LayeredImage remote = readExrBytes(exr.bytes);
    LayeredImage local =
        renderInProcess(kScenes / "cornell-point" / "cornell-point.gltf", 32, 24, 4, 5, "bdpt");
    ASSERT_NE(local.layer("LSSDE"), nullptr) << "the point light's caustic, by light tracing";
    EXPECT_EQ(compareImages(remote, local), "");
}

TEST(ServiceRender, PreviewsArriveAndTheFinalFrameIsTheResult) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::JobSpec spec = sceneSpec("cornell", 96, 72, 64, 3);
    spec.set_preview_interval_seconds(0.1);
    Submitted job = submit(*stub, spec);
    ASSERT_TRUE(job.status.ok()) << job.status.error_message();
    WatchLog log = watch(*stub, job.id, /*previews=*/true, /*raw=*/true);
    ASSERT_TRUE(log.status.ok()) << log.status.error_message();
    ASSERT_FALSE(log.events.empty());
    EXPECT_TRUE(log.events.front().has_state()) << "a watch starts with the job's state";
    ASSERT_TRUE(log.last());
    ASSERT_EQ(log.last()->state(), pb::JOB_STATE_DONE) << log.last()->error();
    EXPECT_TRUE(log.events.back().has_state()) << "the terminal state comes last";

    auto frames = log.frames();
    ASSERT_GE(frames.size(), 2u) << "expected previews during the render and a final frame";
    uint64_t previous = 0;
    for (size_t i = 0; i < frames.size(); ++i) {
        const pb::PreviewFrame& f = *frames[i];
        EXPECT_GT(f.sequence(), previous);
        previous = f.sequence();
        EXPECT_EQ(f.final(), i + 1 == frames.size());
        ASSERT_GE(f.layers_size(), 2) << "combined and at least one type layer";
        EXPECT_EQ(f.layers(0).name(), "combined");
        for (const auto& layer : f.layers()) {
            EXPECT_EQ(layer.width(), 96);
            EXPECT_EQ(layer.height(), 72);
            ASSERT_GE(layer.png().size(), 8u);
            EXPECT_EQ(layer.png().substr(1, 3), "PNG");
            EXPECT_EQ(layer.raw_rgb_f32().size(), size_t(96 * 72 * 3 * 4));
            if (&layer != &f.layers(0)) {
                EXPECT_TRUE(layer.name() == "other" ||
                            (layer.name().front() == 'L' && layer.name().back() == 'E'))
                    << layer.name();
            }
        }
    }
    // The last frame before the state DONE is the final one and equals the result file.
    Fetched exr = fetch(*stub, job.id, pb::RESULT_KIND_EXR);
    ASSERT_TRUE(exr.status.ok());
    EXPECT_EQ(compareImages(frameImage(*frames.back()), readExrBytes(exr.bytes)), "");
    // The frame's PNG has the very pixels of the result's preview.png (written by the core's
    // writePng with the same automatic exposure).
    Fetched png = fetch(*stub, job.id, pb::RESULT_KIND_PNG);
    ASSERT_TRUE(png.status.ok());
    LayeredImage framePng = readExrBytes(frames.back()->layers(0).png(), "frame.png");
    LayeredImage resultPng = readExrBytes(png.bytes, "preview.png");
    EXPECT_EQ(framePng.combined.width, 96);
    EXPECT_EQ(compareImages(framePng, resultPng), "");
}

TEST(ServiceRender, PngAndMetadataAndChunkedExr) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::JobSpec spec = sceneSpec("cornell-glass", 256, 192, 1, 5);
    spec.set_label("chunks");
    Submitted job = submit(*stub, spec);
    ASSERT_TRUE(job.status.ok());
    ASSERT_EQ(waitForEnd(*stub, job.id).state(), pb::JOB_STATE_DONE);

    Fetched exr = fetch(*stub, job.id, pb::RESULT_KIND_EXR);
    ASSERT_TRUE(exr.status.ok());
    EXPECT_TRUE(exr.chunksConsistent);
    ASSERT_GT(exr.bytes.size(), size_t(1) << 20) << "want a result larger than one chunk";
    EXPECT_EQ(exr.chunks, (exr.bytes.size() + (1 << 20) - 1) >> 20) << "1 MiB chunks";
    EXPECT_EQ(readExrBytes(exr.bytes).combined.width, 256);

    Fetched png = fetch(*stub, job.id, pb::RESULT_KIND_PNG);
    ASSERT_TRUE(png.status.ok());
    EXPECT_EQ(png.bytes.substr(1, 3), "PNG");

    Fetched meta = fetch(*stub, job.id, pb::RESULT_KIND_METADATA);
    ASSERT_TRUE(meta.status.ok());
    auto j = nlohmann::json::parse(meta.bytes);
    EXPECT_EQ(j["job_id"], job.id);
    EXPECT_EQ(j["label"], "chunks");
    EXPECT_EQ(j["algorithm"], "pt");
    EXPECT_EQ(j["scene"], "cornell-glass");
    EXPECT_EQ(j["parameters"]["width"], 256);
    EXPECT_EQ(j["parameters"]["seed"], 5);
    EXPECT_EQ(j["stats"]["spp"], 1.0);
    EXPECT_TRUE(j["layers"].is_array());

    // Store layout: <store>/jobs/<id>/{result.exr, preview.png, metadata.json}.
    for (const char* name : {"result.exr", "preview.png", "metadata.json"})
        EXPECT_TRUE(fs::exists(store.path() / "jobs" / job.id / name)) << name;
}

TEST(ServiceRender, UploadedGltfRendersLikeTheNamedSceneAndGlbUploadsWork) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();

    pb::JobSpec named = sceneSpec("cornell", 32, 24, 4, 11);
    pb::JobSpec uploaded = named;
    pb::GltfUpload* up = uploaded.mutable_scene()->mutable_gltf();
    up->set_gltf(readFile(kScenes / "cornell" / "cornell.gltf"));
    pb::Resource* bin = up->add_resources();
    bin->set_uri("cornell.bin");
    bin->set_data(readFile(kScenes / "cornell" / "cornell.bin"));

    pb::JobSpec glb;
    glb.mutable_scene()->set_glb(makeGridGlb(40));
    glb.set_width(24);
    glb.set_height(16);

    Submitted a = submit(*stub, named), b = submit(*stub, uploaded), c = submit(*stub, glb);
    ASSERT_TRUE(a.status.ok() && b.status.ok() && c.status.ok()) << b.status.error_message();
    // The echoed spec carries no scene bytes.
    pb::GetJobRequest get;
    get.set_job_id(b.id);
    pb::Job echoed;
    auto ctx = context();
    ASSERT_TRUE(stub->GetJob(ctx.get(), get, &echoed).ok());
    EXPECT_TRUE(echoed.spec().scene().has_gltf());
    EXPECT_TRUE(echoed.spec().scene().gltf().gltf().empty());
    EXPECT_TRUE(echoed.spec().scene().gltf().resources(0).data().empty());

    for (const auto& id : {a.id, b.id, c.id}) {
        pb::Job end = waitForEnd(*stub, id);
        ASSERT_EQ(end.state(), pb::JOB_STATE_DONE) << end.error();
    }
    Fetched ra = fetch(*stub, a.id, pb::RESULT_KIND_EXR),
            rb = fetch(*stub, b.id, pb::RESULT_KIND_EXR);
    EXPECT_EQ(compareImages(readExrBytes(ra.bytes), readExrBytes(rb.bytes)), "");
    EXPECT_EQ(readExrBytes(fetch(*stub, c.id, pb::RESULT_KIND_EXR).bytes).combined.width, 24);
}

TEST(ServiceRender, ServerInfoScenesListAndDelete) {
    TempDir store;
    Daemon daemon(store.path(), {"--max-jobs", "3", "--max-width", "4000"});
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();

    pb::ServerInfo info;
    auto ctx = context();
    ASSERT_TRUE(stub->GetServerInfo(ctx.get(), {}, &info).ok());
    EXPECT_FALSE(info.version().empty());
    EXPECT_EQ(info.threads(), 2);
    EXPECT_EQ(info.max_concurrent_jobs(), 3);
    EXPECT_EQ(info.limits().max_width(), 4000);
    bool hasPt = false;
    for (const auto& a : info.algorithms())
        if (a.name() == "pt") hasPt = a.native_budget() == pb::BUDGET_KIND_SAMPLES_PER_PIXEL;
    EXPECT_TRUE(hasPt);

    pb::ListScenesResponse scenes;
    ctx = context();
    ASSERT_TRUE(stub->ListScenes(ctx.get(), {}, &scenes).ok());
    std::map<std::string, std::string> byName;
    for (const auto& s : scenes.scenes()) byName[s.name()] = s.file();
    EXPECT_EQ(byName["cornell"], "cornell/cornell.gltf");
    EXPECT_TRUE(byName.count("cornell-glass"));
    EXPECT_FALSE(byName.count("generate"));

    pb::JobSpec spec = sceneSpec("cornell", 16, 12, 1);
    spec.set_label("mine");
    Submitted a = submit(*stub, spec);
    spec.set_label("other");
    Submitted b = submit(*stub, spec);
    ASSERT_TRUE(a.status.ok() && b.status.ok());
    ASSERT_EQ(waitForEnd(*stub, a.id).state(), pb::JOB_STATE_DONE);
    ASSERT_EQ(waitForEnd(*stub, b.id).state(), pb::JOB_STATE_DONE);

    pb::ListJobsRequest list;
    list.set_label("mine");
    pb::ListJobsResponse jobs;
    ctx = context();
    ASSERT_TRUE(stub->ListJobs(ctx.get(), list, &jobs).ok());
    ASSERT_EQ(jobs.jobs_size(), 1);
    EXPECT_EQ(jobs.jobs(0).id(), a.id);
    list.clear_label();
    list.add_states(pb::JOB_STATE_DONE);
    ctx = context();
    ASSERT_TRUE(stub->ListJobs(ctx.get(), list, &jobs).ok());
    EXPECT_EQ(jobs.jobs_size(), 2);
    list.clear_states();
    list.add_states(pb::JOB_STATE_QUEUED);
    ctx = context();
    ASSERT_TRUE(stub->ListJobs(ctx.get(), list, &jobs).ok());
    EXPECT_EQ(jobs.jobs_size(), 0);

    pb::DeleteJobRequest del;
    del.set_job_id(a.id);
    pb::DeleteJobResponse deleted;
    ctx = context();
    ASSERT_TRUE(stub->DeleteJob(ctx.get(), del, &deleted).ok());
    EXPECT_FALSE(fs::exists(store.path() / "jobs" / a.id));
    pb::GetJobRequest get;
    get.set_job_id(a.id);
    pb::Job gone;
    ctx = context();
    EXPECT_EQ(stub->GetJob(ctx.get(), get, &gone).error_code(), grpc::StatusCode::NOT_FOUND);
}

TEST(ServiceRender, HealthServiceAnswersServing) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    // grpc.health.v1.Health/Check with an empty request (service ""), over a generic stub.
    grpc::GenericStub generic(daemon.channel());
    grpc::CompletionQueue cq;
    grpc::ByteBuffer request, response;
    grpc::Slice empty("");
    request = grpc::ByteBuffer(&empty, 1);
    auto ctx = context(10s);
    auto call = generic.PrepareUnaryCall(ctx.get(), "/grpc.health.v1.Health/Check", request, &cq);
    call->StartCall();
    grpc::Status status;
    call->Finish(&response, &status, reinterpret_cast<void*>(1));
    void* tag = nullptr;
    bool ok = false;
    ASSERT_TRUE(cq.Next(&tag, &ok));
    ASSERT_TRUE(status.ok()) << status.error_message();
    std::vector<grpc::Slice> slices;
    ASSERT_TRUE(response.Dump(&slices).ok());
    std::string bytes;
    for (const auto& s : slices) bytes.append(reinterpret_cast<const char*>(s.begin()), s.size());
    EXPECT_EQ(bytes, std::string("\x08\x01", 2)) << "HealthCheckResponse{status: SERVING}";
    cq.Shutdown();
    while (cq.Next(&tag, &ok)) {
    }
}

}  // namespace
}  // namespace partita::test
