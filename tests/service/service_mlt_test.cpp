// mlt through the daemon: its phases (the BDPT bootstrap as PREPASS, then the chains in
// mutations), the running acceptance per mutation type in progress events, previews, the result
// and its metadata, cancelling in either phase, and its errors (an orthographic camera fails the
// job; samples per pixel are refused at submit).
#include <gtest/gtest.h>

#include <future>
#include <nlohmann/json.hpp>

#include "in_process.h"
#include "mcmc/startup_rule.h"
#include "service_client.h"

namespace partita::test {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

const fs::path kScenes = PARTITA_SCENES_DIR;
const std::vector<std::string> kMutations = {"bidirectional", "caustic", "lens", "multi_chain"};

pb::JobSpec mltSpec(const std::string& scene, int width, int height, double mpp,
                    uint64_t seed = 1) {
    pb::JobSpec spec = sceneSpec(scene, width, height, mpp, seed);
    spec.set_algorithm("mlt");
    spec.mutable_budget()->set_kind(pb::BUDGET_KIND_MUTATIONS_PER_PIXEL);
    return spec;
}

void cancel(pb::Partita::Stub& stub, const std::string& id) {
    pb::CancelJobRequest request;
    request.set_job_id(id);
    pb::Job job;
    auto ctx = context(10s);
    grpc::Status s = stub.CancelJob(ctx.get(), request, &job);
    EXPECT_TRUE(s.ok()) << s.error_message();
}

TEST(ServiceMlt, JobHasBootstrapAndRenderPhasesAcceptanceAPreviewLayersAndStats) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    // 2048 mutations per pixel: 256 chains of 1536 mutations, two rounds (of 1024 and 512), so
    // the preview after the first comes well before the final frame, which would replace a
    // preview still waiting to be sent.
    constexpr double kMpp = 2048;
    pb::JobSpec spec = mltSpec("cornell", 16, 12, kMpp, 3);
    spec.set_preview_interval_seconds(0.05);
    Submitted job = submit(*stub, spec);
    ASSERT_TRUE(job.status.ok()) << job.status.error_message();
    WatchLog log = watch(*stub, job.id, /*previews=*/true);
    ASSERT_TRUE(log.status.ok()) << log.status.error_message();
    ASSERT_TRUE(log.last());
    ASSERT_EQ(log.last()->state(), pb::JOB_STATE_DONE) << log.last()->error();

    // The bootstrap is the pre-pass: PREPASS, then RENDERING, in order.
    std::vector<pb::JobState> states = log.states();
    EXPECT_TRUE(std::is_sorted(states.begin(), states.end())) << "states went backwards";
    EXPECT_NE(std::find(states.begin(), states.end(), pb::JOB_STATE_PREPASS), states.end());
    EXPECT_NE(std::find(states.begin(), states.end(), pb::JOB_STATE_RENDERING), states.end());

    // Progress: "bootstrap" in samples while PREPASS, "render" in mutations while RENDERING; the
    // phase's last report (done == total) always reaches the watcher, with the acceptance.
    pb::JobState state = pb::JOB_STATE_UNSPECIFIED;
    std::vector<pb::Progress> bootstrap, render;
    for (const auto& e : log.events) {
        if (e.has_state()) state = e.state().state();
        if (!e.has_progress()) continue;
        const pb::Progress& p = e.progress();
        if (p.phase() == "bootstrap") {
            EXPECT_EQ(state, pb::JOB_STATE_PREPASS);
            EXPECT_EQ(p.unit(), "samples");
            EXPECT_TRUE(render.empty()) << "bootstrap progress after the render's";
            bootstrap.push_back(p);
        } else {
            EXPECT_EQ(p.phase(), "render");
            EXPECT_EQ(state, pb::JOB_STATE_RENDERING);
            render.push_back(p);
        }
    }
    ASSERT_FALSE(bootstrap.empty());
    // The start-up rule's samples (mcmc/startup_rule.h) for 16 x 12 x kMpp mutations.
    RenderSettings rule;
    rule.width = 16;
    rule.height = 12;
    rule.budgetKind = BudgetKind::MutationsPerPixel;
    rule.budget = kMpp;
    const uint64_t samples = StartupRule::bootstrapSamples(0, rule);
    EXPECT_EQ(samples, 78644u) << "393216 mutations, a sample costing five";
    EXPECT_EQ(bootstrap.back().done(), samples) << "mlt's default bootstrap";
    EXPECT_EQ(bootstrap.back().total(), samples);
    ASSERT_FALSE(render.empty());
    const pb::Progress& last = render.back();
    EXPECT_EQ(last.unit(), "mutations");
    EXPECT_EQ(last.total(), 16 * 12 * kMpp) << "the budget in mutations";
    EXPECT_EQ(last.done(), last.total());
    EXPECT_GT(last.rate_per_second(), 0) << "a rate in mutations per second";
    EXPECT_GE(last.eta_seconds(), 0) << "an ETA";
    EXPECT_EQ(last.values().at("mutations"), last.total());
    for (const std::string& name : {std::string("bidirectional"), std::string("lens")}) {
        ASSERT_TRUE(last.values().count("acceptance_" + name)) << name;
        double a = last.values().at("acceptance_" + name);
        EXPECT_TRUE(a > 0 && a <= 1) << name << " " << a;
    }
    for (const auto& [key, value] : last.values())
        EXPECT_TRUE(key == "mutations" || key == "error_estimate" ||
                    key.rfind("acceptance_", 0) == 0)
            << key;
    // The render's own error estimate (two halves of its chains, issue #26).
    ASSERT_TRUE(last.values().count("error_estimate"));
    EXPECT_GT(last.values().at("error_estimate"), 0.0);

    // A preview during the chains, then the final frame.
    auto frames = log.frames();
    ASSERT_GE(frames.size(), 2u) << "a preview and the final frame";
    EXPECT_FALSE(frames.front()->final());
    EXPECT_EQ(frames.front()->layers(0).name(), "combined");
    EXPECT_TRUE(frames.back()->final());

    // The result: combined and per-type layers, the very image mlt renders in-process.
    Fetched exr = fetch(*stub, job.id, pb::RESULT_KIND_EXR);
    ASSERT_TRUE(exr.status.ok()) << exr.status.error_message();
    LayeredImage remote = readExrBytes(exr.bytes);
    EXPECT_EQ(remote.combined.width, 16);
    EXPECT_EQ(remote.combined.height, 12);
    ASSERT_GT(remote.layers.size(), 1u) << "per-type layers";
    for (const auto& l : remote.layers)
        EXPECT_TRUE(l.name == "other" || (l.name.front() == 'L' && l.name.back() == 'E')) << l.name;
    EXPECT_NE(remote.layer("LDE"), nullptr);
    EXPECT_GT(luminance(remote.combined.mean()), 0.0f);
    LayeredImage local =
        renderInProcess(kScenes / "cornell" / "cornell.gltf", 16, 12, kMpp, 3, "mlt");
    EXPECT_EQ(compareImages(remote, local), "");

    // The metadata and the job's statistics: b, the bootstrap, acceptance per mutation type.
    Fetched meta = fetch(*stub, job.id, pb::RESULT_KIND_METADATA);
    ASSERT_TRUE(meta.status.ok());
    auto j = nlohmann::json::parse(meta.bytes);
    EXPECT_EQ(j["algorithm"], "mlt");
    EXPECT_EQ(j["parameters"]["budget_kind"], "mpp");
    EXPECT_EQ(j["parameters"]["budget"], kMpp);
    const auto& stats = j["stats"];
    EXPECT_GT(stats["b"].get<double>(), 0);
    EXPECT_EQ(stats["bootstrap_samples"], double(samples));
    EXPECT_EQ(stats["mutations"], 16.0 * 12 * kMpp);
    EXPECT_EQ(stats["chains"], 256.0);
    for (const std::string& name : kMutations) {
        ASSERT_TRUE(stats.contains("acceptance_" + name)) << name << "\n" << stats.dump(1);
        ASSERT_TRUE(stats.contains("proposed_" + name)) << name;
        double a = stats["acceptance_" + name].get<double>();
        EXPECT_TRUE(a >= 0 && a <= 1) << name << " " << a;
    }
    EXPECT_EQ(stats["acceptance_bidirectional"].get<double>(),
              last.values().at("acceptance_bidirectional"))
        << "the last progress has the final acceptance";
    EXPECT_TRUE(log.last()->stats().count("acceptance_lens")) << "GetJob's stats too";
}

TEST(ServiceMlt, CancelDuringTheBootstrapEndsTheJobWithinASecond) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    // pool: 100000 BDPT bootstrap samples take about 1.4 s on 2 threads.
    pb::JobSpec spec = mltSpec("pool", 64, 48, 64);
    spec.set_bootstrap_samples(100000);
    Submitted job = submit(*stub, spec);
    ASSERT_TRUE(job.status.ok()) << job.status.error_message();
    auto ctx = context();
    auto reader = stub->WatchJob(ctx.get(), watchRequest(job.id));
    pb::JobEvent event;
    bool prepass = false;
    while (!prepass && reader->Read(&event))
        prepass = event.has_state() && event.state().state() == pb::JOB_STATE_PREPASS;
    ASSERT_TRUE(prepass);
    auto start = Clock::now();
    cancel(*stub, job.id);
    std::vector<pb::JobState> states;
    std::vector<std::string> phases;
    while (reader->Read(&event)) {
        if (event.has_state()) states.push_back(event.state().state());
        if (event.has_progress()) phases.push_back(event.progress().phase());
    }
    double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    EXPECT_TRUE(reader->Finish().ok());
    EXPECT_EQ(states, std::vector<pb::JobState>{pb::JOB_STATE_CANCELLED})
        << "cancelled in the bootstrap: it never renders";
    for (const auto& phase : phases) EXPECT_EQ(phase, "bootstrap");
    EXPECT_LT(seconds, 1.0) << "the bootstrap polls the cancel flag";
    std::printf("cancel in the bootstrap took %.3f s\n", seconds);

    // The daemon goes on serving.
    Submitted next = submit(*stub, mltSpec("cornell", 16, 12, 1));
    ASSERT_TRUE(next.status.ok()) << next.status.error_message();
    EXPECT_EQ(waitForEnd(*stub, next.id).state(), pb::JOB_STATE_DONE);
}

TEST(ServiceMlt, CancelDuringTheChainsEndsTheJobWithinASecond) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::JobSpec spec = mltSpec("cornell", 160, 120, 1);
    spec.mutable_budget()->set_kind(pb::BUDGET_KIND_SECONDS);
    spec.mutable_budget()->set_amount(60);
    Submitted job = submit(*stub, spec);
    ASSERT_TRUE(job.status.ok()) << job.status.error_message();
    auto ctx = context();
    auto reader = stub->WatchJob(ctx.get(), watchRequest(job.id));
    pb::JobEvent event;
    bool chains = false;  // a report of mutations done
    while (!chains && reader->Read(&event))
        chains = event.has_progress() && event.progress().phase() == "render" &&
                 event.progress().done() > 0;
    ASSERT_TRUE(chains);
    auto start = Clock::now();
    cancel(*stub, job.id);
    std::vector<pb::JobState> states;
    while (reader->Read(&event))
        if (event.has_state()) states.push_back(event.state().state());
    double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    EXPECT_TRUE(reader->Finish().ok());
    EXPECT_EQ(states, std::vector<pb::JobState>{pb::JOB_STATE_CANCELLED});
    EXPECT_LT(seconds, 1.0) << "the chains poll the cancel flag";
    std::printf("cancel in the chains took %.3f s\n", seconds);
}

TEST(ServiceMlt, OrthographicCameraFailsTheJobWithAClearMessageAndTheDaemonServesOn) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    // cornell with its camera made orthographic, uploaded.
    auto gltf = nlohmann::json::parse(readFile(kScenes / "cornell" / "cornell.gltf"));
    gltf["cameras"][0] = {
        {"name", "main"},
        {"type", "orthographic"},
        {"orthographic", {{"xmag", 1.3}, {"ymag", 1.0}, {"znear", 0.01}, {"zfar", 100.0}}}};
    pb::JobSpec spec = mltSpec("cornell", 16, 12, 4);
    pb::GltfUpload* up = spec.mutable_scene()->mutable_gltf();
    up->set_gltf(gltf.dump());
    pb::Resource* bin = up->add_resources();
    bin->set_uri("cornell.bin");
    bin->set_data(readFile(kScenes / "cornell" / "cornell.bin"));
    spec.set_scene_file("cornell-ortho.gltf");

    // The camera is known once the scene is loaded, so the job is accepted and then fails.
    Submitted job = submit(*stub, spec);
    ASSERT_TRUE(job.status.ok()) << job.status.error_message();
    pb::Job end = waitForEnd(*stub, job.id);
    EXPECT_EQ(end.state(), pb::JOB_STATE_FAILED);
    EXPECT_NE(end.error().find("mlt needs a perspective camera"), std::string::npos) << end.error();
    EXPECT_NE(end.error().find("orthographic"), std::string::npos) << end.error();
    EXPECT_EQ(fetch(*stub, job.id, pb::RESULT_KIND_EXR).status.error_code(),
              grpc::StatusCode::FAILED_PRECONDITION);

    // The same upload renders with pt, and mlt with a perspective camera renders on.
    pb::JobSpec pt = spec;
    pt.set_algorithm("pt");
    pt.mutable_budget()->set_kind(pb::BUDGET_KIND_SAMPLES_PER_PIXEL);
    Submitted ok = submit(*stub, pt);
    ASSERT_TRUE(ok.status.ok()) << ok.status.error_message();
    EXPECT_EQ(waitForEnd(*stub, ok.id).state(), pb::JOB_STATE_DONE);
    Submitted perspective = submit(*stub, mltSpec("cornell", 16, 12, 1));
    ASSERT_TRUE(perspective.status.ok()) << perspective.status.error_message();
    EXPECT_EQ(waitForEnd(*stub, perspective.id).state(), pb::JOB_STATE_DONE);
}

TEST(ServiceMlt, SamplesPerPixelAreRefusedAtSubmit) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::JobSpec spec = mltSpec("cornell", 16, 12, 4);
    spec.mutable_budget()->set_kind(pb::BUDGET_KIND_SAMPLES_PER_PIXEL);
    Submitted r = submit(*stub, spec);
    EXPECT_EQ(r.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_NE(r.status.error_message().find(
                  "algorithm 'mlt' takes its budget in mutations per pixel or seconds, not "
                  "samples per pixel"),
              std::string::npos)
        << r.status.error_message();

    pb::ServerInfo info;
    auto ctx = context(10s);
    ASSERT_TRUE(stub->GetServerInfo(ctx.get(), {}, &info).ok());
    bool listed = false;
    for (const auto& a : info.algorithms())
        if (a.name() == "mlt") listed = a.native_budget() == pb::BUDGET_KIND_MUTATIONS_PER_PIXEL;
    EXPECT_TRUE(listed) << "GetServerInfo lists mlt with its budget in mutations per pixel";
}

}  // namespace
}  // namespace partita::test
