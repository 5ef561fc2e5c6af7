// guided through the daemon, as a user runs it: the phases (the pre-pass and then the guides
// while the job is PREPASS, then the chains while RENDERING), the partitions in progress, the
// result with one layer per partition adding up to the combined image, and the metadata: the
// job's |Y'|, R and epsilon applied and shown, the guides' statistics.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "in_process.h"
#include "service_client.h"

namespace partita::test {
namespace {

TEST(ServiceGuided, JobRunsPrepassGuidesThenChainsWithItsParameters) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::JobSpec spec = sceneSpec("cornell-glass", 16, 12, 256, 5);
    spec.set_algorithm("guided");
    spec.mutable_budget()->set_kind(pb::BUDGET_KIND_MUTATIONS_PER_PIXEL);
    spec.set_bootstrap_samples(4000);
    spec.set_k(3);
    spec.set_y(33);
    spec.set_radius(4);
    spec.set_epsilon(0.05f);
    // Every partition with chains, the guided move's (estimators=auto sends this small image's
    // partitions per pixel, after a pilot phase).
    (*spec.mutable_parameters())["estimators"].set_text_value("chains");
    Submitted job = submit(*stub, spec);
    ASSERT_TRUE(job.status.ok()) << job.status.error_message();
    WatchLog log = watch(*stub, job.id, /*previews=*/false);
    ASSERT_TRUE(log.status.ok()) << log.status.error_message();
    ASSERT_TRUE(log.last());
    ASSERT_EQ(log.last()->state(), pb::JOB_STATE_DONE) << log.last()->error();

    // Phases in order, each in its state: prepass and guides in PREPASS, render in RENDERING.
    pb::JobState state = pb::JOB_STATE_UNSPECIFIED;
    std::vector<std::string> phases;
    for (const auto& e : log.events) {
        if (e.has_state()) state = e.state().state();
        if (!e.has_progress()) continue;
        const std::string& phase = e.progress().phase();
        if (phases.empty() || phases.back() != phase) phases.push_back(phase);
        EXPECT_EQ(state, phase == "render" ? pb::JOB_STATE_RENDERING : pb::JOB_STATE_PREPASS)
            << phase;
    }
    EXPECT_EQ(phases, (std::vector<std::string>{"prepass", "guides", "render"}));

    Fetched exr = fetch(*stub, job.id, pb::RESULT_KIND_EXR);
    ASSERT_TRUE(exr.status.ok()) << exr.status.error_message();
    LayeredImage remote = readExrBytes(exr.bytes);
    ASSERT_GE(remote.layers.size(), 2u);
    EXPECT_EQ(remote.layers.back().name, "complement");
    EXPECT_GT(luminance(remote.combined.mean()), 0.0f);
    for (size_t i = 0; i < remote.combined.rgb.size(); ++i) {
        float sum = 0;
        for (const auto& l : remote.layers) sum += l.image.rgb[i];
        ASSERT_NEAR(sum, remote.combined.rgb[i], 1e-5f * std::max(1.0f, remote.combined.rgb[i]));
    }

    Fetched meta = fetch(*stub, job.id, pb::RESULT_KIND_METADATA);
    ASSERT_TRUE(meta.status.ok());
    auto j = nlohmann::json::parse(meta.bytes);
    EXPECT_EQ(j["algorithm"], "guided");
    EXPECT_EQ(j["parameters"]["y"], 33);
    EXPECT_EQ(j["parameters"]["radius"], 4.0);
    EXPECT_EQ(j["stats"]["guide_candidates"], 33.0);
    EXPECT_EQ(j["stats"]["guide_radius"], 4.0);
    EXPECT_NEAR(j["stats"]["guide_epsilon"].get<double>(), 0.05, 1e-6);
    EXPECT_GT(j["stats"]["proposed_guided"].get<double>(), 0);
    EXPECT_GT(j["stats"]["guide_bytes"].get<double>(), 0);
}

}  // namespace
}  // namespace partita::test
