// partitioned through the daemon: its phases (the pre-pass as PREPASS, then the partitions'
// chains in mutations), the partitions in progress events (type, P(i), b_i, acceptance),
// previews and the result with one layer per partition, the metadata (the pre-pass's choice,
// the partition statistics), cancelling in either phase, and the JobSpec's prepass and
// bootstrap_samples (applied, shown, and INVALID_ARGUMENT when wrong).
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "in_process.h"
#include "service_client.h"

namespace partita::test {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

pb::JobSpec partitionedSpec(const std::string& scene, int width, int height, double mpp,
                            uint64_t bootstrap = 4000, uint64_t seed = 1) {
    pb::JobSpec spec = sceneSpec(scene, width, height, mpp, seed);
    spec.set_algorithm("partitioned");
    spec.mutable_budget()->set_kind(pb::BUDGET_KIND_MUTATIONS_PER_PIXEL);
    spec.set_bootstrap_samples(bootstrap);
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

TEST(ServicePartitioned, JobHasPrepassThenPartitionsInProgressLayersAndStats) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    // 2048 mutations per pixel over 256 chains: two rounds, so a preview comes before the end.
    constexpr double kMpp = 2048;
    pb::JobSpec spec = partitionedSpec("cornell-glass", 16, 12, kMpp, 4000, 3);
    spec.set_k(3);
    spec.set_prepass("pt");
    spec.set_preview_interval_seconds(0.05);
    Submitted job = submit(*stub, spec);
    ASSERT_TRUE(job.status.ok()) << job.status.error_message();
    WatchLog log = watch(*stub, job.id, /*previews=*/true);
    ASSERT_TRUE(log.status.ok()) << log.status.error_message();
    ASSERT_TRUE(log.last());
    ASSERT_EQ(log.last()->state(), pb::JOB_STATE_DONE) << log.last()->error();
    EXPECT_EQ(log.last()->spec().prepass(), "pt");
    EXPECT_EQ(log.last()->spec().bootstrap_samples(), 4000u);

    std::vector<pb::JobState> states = log.states();
    EXPECT_TRUE(std::is_sorted(states.begin(), states.end())) << "states went backwards";
    EXPECT_NE(std::find(states.begin(), states.end(), pb::JOB_STATE_PREPASS), states.end());
    EXPECT_NE(std::find(states.begin(), states.end(), pb::JOB_STATE_RENDERING), states.end());

    // "prepass" in samples while PREPASS (no partitions yet), then the estimators' pilots
    // (estimators=auto, the default), "render" while RENDERING with the partitions: the
    // per-pixel partitions' samples, then the chains' mutations.
    pb::JobState state = pb::JOB_STATE_UNSPECIFIED;
    std::vector<pb::Progress> prepass, render;
    for (const auto& e : log.events) {
        if (e.has_state()) state = e.state().state();
        if (!e.has_progress()) continue;
        const pb::Progress& p = e.progress();
        if (p.phase() == "prepass") {
            EXPECT_EQ(state, pb::JOB_STATE_PREPASS);
            EXPECT_EQ(p.unit(), "samples");
            EXPECT_EQ(p.partitions_size(), 0);
            EXPECT_TRUE(render.empty()) << "pre-pass progress after the render's";
            prepass.push_back(p);
        } else if (p.phase() == "pilot") {
            EXPECT_EQ(state, pb::JOB_STATE_PREPASS);
            EXPECT_FALSE(prepass.empty()) << "the pilots before the pre-pass";
            EXPECT_TRUE(render.empty()) << "pilot progress after the render's";
        } else {
            EXPECT_EQ(p.phase(), "render");
            EXPECT_EQ(state, pb::JOB_STATE_RENDERING);
            render.push_back(p);
        }
    }
    ASSERT_FALSE(prepass.empty());
    EXPECT_EQ(prepass.back().done(), 4000) << "bootstrap_samples applied";
    ASSERT_FALSE(render.empty());
    const pb::Progress& last = render.back();
    EXPECT_EQ(last.done(), last.total());
    ASSERT_GE(last.partitions_size(), 2) << "some types and the complement";
    double sumP = 0;
    std::vector<std::string> types, estimators;
    for (const auto& part : last.partitions()) {
        EXPECT_TRUE(part.type() == "complement" || part.type() == "direct" ||
                    (part.type().front() == 'L' && part.type().back() == 'E'))
            << part.type();
        EXPECT_TRUE(part.estimator() == "chains" || part.estimator() == "per-pixel")
            << part.estimator();
        if (part.type() == "direct") {
            EXPECT_EQ(part.estimator(), "per-pixel");
        }
        estimators.push_back(part.estimator());
        EXPECT_GT(part.b(), 0) << part.type();
        EXPECT_GT(part.p(), 0) << part.type();
        EXPECT_TRUE(part.acceptance() >= 0 && part.acceptance() <= 1) << part.type();
        sumP += part.p();
        types.push_back(part.type());
    }
    EXPECT_NEAR(sumP, 1.0, 1e-9);
    EXPECT_LE(last.partitions_size(), 5) << "K = 3, the direct light and the complement";

    // Previews carry the combined image and every partition's layer.
    auto frames = log.frames();
    ASSERT_GE(frames.size(), 2u) << "a preview and the final frame";
    EXPECT_FALSE(frames.front()->final());
    ASSERT_EQ(frames.front()->layers_size(), int(types.size()) + 1);
    EXPECT_EQ(frames.front()->layers(0).name(), "combined");
    for (size_t g = 0; g < types.size(); ++g)
        EXPECT_EQ(frames.front()->layers(int(g) + 1).name(), types[g]);
    EXPECT_GT(frames.front()->layers(1).png().size(), 0u);

    // The EXR: the combined image and one layer per partition, which add up to it.
    Fetched exr = fetch(*stub, job.id, pb::RESULT_KIND_EXR);
    ASSERT_TRUE(exr.status.ok()) << exr.status.error_message();
    LayeredImage remote = readExrBytes(exr.bytes);
    ASSERT_EQ(remote.layers.size(), types.size());
    for (size_t g = 0; g < types.size(); ++g) EXPECT_EQ(remote.layers[g].name, types[g]);
    EXPECT_EQ(types.back(), "complement") << "cornell-glass has more than 3 types";
    EXPECT_GT(luminance(remote.combined.mean()), 0.0f);
    for (size_t i = 0; i < remote.combined.rgb.size(); ++i) {
        float sum = 0;
        for (const auto& l : remote.layers) sum += l.image.rgb[i];
        ASSERT_NEAR(sum, remote.combined.rgb[i], 1e-5f * std::max(1.0f, remote.combined.rgb[i]))
            << "component " << i;
    }

    // The metadata: the pre-pass's choice and size, the partition statistics.
    Fetched meta = fetch(*stub, job.id, pb::RESULT_KIND_METADATA);
    ASSERT_TRUE(meta.status.ok());
    auto j = nlohmann::json::parse(meta.bytes);
    EXPECT_EQ(j["algorithm"], "partitioned");
    EXPECT_EQ(j["parameters"]["prepass"], "pt");
    EXPECT_EQ(j["parameters"]["bootstrap"], 4000);
    EXPECT_EQ(j["parameters"]["k"], 3);
    EXPECT_FALSE(j["labels"]["prepass"].get<std::string>().empty()) << j["labels"].dump(1);
    const auto& stats = j["stats"];
    EXPECT_EQ(stats["prepass_samples"], 4000.0);
    EXPECT_EQ(stats["partitions"], double(types.size()));
    for (size_t g = 0; g < types.size(); ++g) {
        std::string key = "partition_" + std::to_string(g) + "_";
        EXPECT_EQ(j["labels"][key + "type"], types[g]);
        EXPECT_EQ(stats[key + "p"].get<double>(), last.partitions(int(g)).p());
        EXPECT_EQ(stats[key + "b"].get<double>(), last.partitions(int(g)).b());
        EXPECT_EQ(stats[key + "acceptance"].get<double>(), last.partitions(int(g)).acceptance())
            << "the last progress has the final acceptance";
        EXPECT_EQ(j["labels"][key + "estimator"], estimators[g]);
        if (estimators[g] == "chains") {
            EXPECT_GT(stats[key + "mutations"].get<double>(), 0);
        } else {
            EXPECT_GT(stats["per_pixel_spp"].get<double>(), 0);
        }
        EXPECT_TRUE(stats.contains(key + "gamma"));
    }
    EXPECT_TRUE(log.last()->stats().count("partition_0_b")) << "GetJob's stats too";
}

TEST(ServicePartitioned, CancelDuringThePrepassEndsTheJobWithinASecond) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    // pool with a BDPT pre-pass of 400000 samples: several seconds on 2 threads.
    pb::JobSpec spec = partitionedSpec("pool", 64, 48, 64, 400000);
    spec.set_prepass("bdpt");
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
        << "cancelled in the pre-pass: it never renders";
    for (const auto& phase : phases) EXPECT_EQ(phase, "prepass");
    EXPECT_LT(seconds, 1.0) << "the pre-pass polls the cancel flag";
    std::printf("cancel in the pre-pass took %.3f s\n", seconds);

    Submitted next = submit(*stub, partitionedSpec("cornell", 16, 12, 1));
    ASSERT_TRUE(next.status.ok()) << next.status.error_message();
    EXPECT_EQ(waitForEnd(*stub, next.id).state(), pb::JOB_STATE_DONE);
}

TEST(ServicePartitioned, CancelDuringTheChainsEndsTheJobWithinASecond) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::JobSpec spec = partitionedSpec("cornell-glass", 160, 120, 1);
    spec.mutable_budget()->set_kind(pb::BUDGET_KIND_SECONDS);
    spec.mutable_budget()->set_amount(60);
    Submitted job = submit(*stub, spec);
    ASSERT_TRUE(job.status.ok()) << job.status.error_message();
    auto ctx = context();
    auto reader = stub->WatchJob(ctx.get(), watchRequest(job.id));
    pb::JobEvent event;
    bool chains = false;  // a report of mutations done, with the partitions
    while (!chains && reader->Read(&event))
        chains = event.has_progress() && event.progress().phase() == "render" &&
                 event.progress().done() > 0 && event.progress().partitions_size() > 0;
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

TEST(ServicePartitioned, ABadPrepassIsInvalidArgumentAndTooManyBootstrapSamplesExhausted) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::JobSpec bad = partitionedSpec("cornell", 16, 12, 4);
    bad.set_prepass("magic");
    Submitted refused = submit(*stub, bad);
    EXPECT_EQ(refused.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_EQ(refused.status.error_message(), "prepass 'magic' is not one of auto | pt | bdpt");

    pb::JobSpec many = partitionedSpec("cornell", 16, 12, 4, uint64_t(1) << 31);
    Submitted over = submit(*stub, many);
    // A limit of this server (GetServerInfo says which), not a malformed request.
    EXPECT_EQ(over.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_EQ(over.status.error_message(),
              "bootstrap = 2147483648 samples exceeds this server's limit of 1073741824");

    // mlt takes bootstrap_samples too; the server lists both algorithms' parameters.
    pb::JobSpec mlt = partitionedSpec("cornell", 16, 12, 4, 2000);
    mlt.set_algorithm("mlt");
    Submitted ok = submit(*stub, mlt);
    ASSERT_TRUE(ok.status.ok()) << ok.status.error_message();
    pb::Job end = waitForEnd(*stub, ok.id);
    EXPECT_EQ(end.state(), pb::JOB_STATE_DONE) << end.error();
    EXPECT_EQ(end.stats().at("bootstrap_samples"), 2000);

    pb::ServerInfo info;
    auto ctx = context(10s);
    ASSERT_TRUE(stub->GetServerInfo(ctx.get(), pb::ServerInfoRequest{}, &info).ok());
    EXPECT_EQ(info.limits().max_bootstrap_samples(), uint64_t(1) << 30);
    for (const auto& a : info.algorithms()) {
        auto has = [&](const char* p) {
            return std::find(a.parameters().begin(), a.parameters().end(), p) !=
                   a.parameters().end();
        };
        if (a.name() == "partitioned") {
            EXPECT_TRUE(has("k") && has("prepass") && has("bootstrap"));
        }
        if (a.name() == "mlt") {
            EXPECT_TRUE(has("bootstrap") && !has("prepass"));
        }
    }
}

}  // namespace
}  // namespace partita::test
