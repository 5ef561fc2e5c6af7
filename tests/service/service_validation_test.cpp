// Every validation error with its status code (DESIGN.md "Service shape"): bad request
// INVALID_ARGUMENT, unknown job NOT_FOUND, limits RESOURCE_EXHAUSTED, wrong state
// FAILED_PRECONDITION. A scene that fails to load fails the job, not the daemon.
#include <gtest/gtest.h>

#include <functional>
#include <future>

#include "service_client.h"

namespace partita::test {
namespace {

using namespace std::chrono_literals;
using Code = grpc::StatusCode;

const std::vector<std::string> kSmallLimits = {"--max-width",     "256", "--max-height",  "200",
                                               "--max-spp",       "64",  "--max-seconds", "10",
                                               "--max-upload-mb", "1",   "--max-depth",   "64"};

struct Case {
    std::string name;
    std::function<void(pb::JobSpec&)> change;
    Code code;
    std::string message;  // a part of the error message
};

/// `change` on a job of guided (its own parameters are k, y, radius, epsilon, ...).
std::function<void(pb::JobSpec&)> guided(std::function<void(pb::JobSpec&)> change) {
    return [change](pb::JobSpec& s) {
        s.set_algorithm("guided");
        s.mutable_budget()->set_kind(pb::BUDGET_KIND_MUTATIONS_PER_PIXEL);
        change(s);
    };
}

TEST(ServiceValidation, EverySpecErrorHasItsCodeAndAClearMessage) {
    TempDir store;
    Daemon daemon(store.path(), kSmallLimits);
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    const std::vector<Case> cases = {
        {"no scene", [](pb::JobSpec& s) { s.clear_scene(); }, Code::INVALID_ARGUMENT,
         "names no scene"},
        {"empty scene name", [](pb::JobSpec& s) { s.mutable_scene()->set_scene_name(""); },
         Code::INVALID_ARGUMENT, "invalid scene name"},
        {"unknown scene", [](pb::JobSpec& s) { s.mutable_scene()->set_scene_name("nope"); },
         Code::NOT_FOUND, "no scene named 'nope'"},
        {"empty glb", [](pb::JobSpec& s) { s.mutable_scene()->set_glb(""); },
         Code::INVALID_ARGUMENT, "GLB is empty"},
        {"upload too large",
         [](pb::JobSpec& s) { s.mutable_scene()->set_glb(std::string(1100000, 'x')); },
         Code::RESOURCE_EXHAUSTED, "--max-upload-mb"},
        {"upload over the message limit",
         [](pb::JobSpec& s) { s.mutable_scene()->set_glb(std::string(18 << 20, 'x')); },
         Code::RESOURCE_EXHAUSTED, ""},
        {"resource uri escapes",
         [](pb::JobSpec& s) {
             s.mutable_scene()->mutable_gltf()->set_gltf("{}");
             auto* r = s.mutable_scene()->mutable_gltf()->add_resources();
             r->set_uri("../secret.bin");
         },
         Code::INVALID_ARGUMENT, "refused"},
        {"unknown algorithm", [](pb::JobSpec& s) { s.set_algorithm("magic"); },
         Code::INVALID_ARGUMENT, "unknown algorithm 'magic' (this server has: bdpt, guided, mlt, "},
        {"zero width", [](pb::JobSpec& s) { s.set_width(0); }, Code::INVALID_ARGUMENT,
         "width = 0 must be >= 1"},
        {"negative height", [](pb::JobSpec& s) { s.set_height(-4); }, Code::INVALID_ARGUMENT,
         "height = -4 must be >= 1"},
        {"too wide", [](pb::JobSpec& s) { s.set_width(1000); }, Code::RESOURCE_EXHAUSTED,
         "limit of 256x200"},
        {"too tall", [](pb::JobSpec& s) { s.set_height(201); }, Code::RESOURCE_EXHAUSTED, "limit"},
        {"too many spp", [](pb::JobSpec& s) { s.mutable_budget()->set_amount(65); },
         Code::RESOURCE_EXHAUSTED, "limit of 64"},
        {"too many seconds",
         [](pb::JobSpec& s) {
             s.mutable_budget()->set_kind(pb::BUDGET_KIND_SECONDS);
             s.mutable_budget()->set_amount(11);
         },
         Code::RESOURCE_EXHAUSTED, "limit of 10 s"},
        {"fractional spp", [](pb::JobSpec& s) { s.mutable_budget()->set_amount(1.5); },
         Code::INVALID_ARGUMENT, "whole number"},
        {"negative budget", [](pb::JobSpec& s) { s.mutable_budget()->set_amount(-1); },
         Code::INVALID_ARGUMENT, "positive"},
        {"unknown budget kind",
         [](pb::JobSpec& s) { s.mutable_budget()->set_kind(pb::BudgetKind(42)); },
         Code::INVALID_ARGUMENT, "unknown budget kind 42"},
        {"unspecified budget kind",
         [](pb::JobSpec& s) { s.mutable_budget()->set_kind(pb::BUDGET_KIND_UNSPECIFIED); },
         Code::INVALID_ARGUMENT, "unspecified"},
        {"mutations for pt",
         [](pb::JobSpec& s) { s.mutable_budget()->set_kind(pb::BUDGET_KIND_MUTATIONS_PER_PIXEL); },
         Code::INVALID_ARGUMENT, "samples per pixel"},
        {"k < 0", guided([](pb::JobSpec& s) { s.set_k(-1); }), Code::INVALID_ARGUMENT,
         "k = -1 is outside [0, 64] partitions"},
        {"|Y'| = 0", guided([](pb::JobSpec& s) { s.set_y(0); }), Code::INVALID_ARGUMENT,
         "y = 0 is outside [1, 4096] pixels"},
        {"negative radius", guided([](pb::JobSpec& s) { s.set_radius(-1); }),
         Code::INVALID_ARGUMENT, "radius = -1 is outside (0, 4096] pixels"},
        {"epsilon > 1", guided([](pb::JobSpec& s) { s.set_epsilon(2); }), Code::INVALID_ARGUMENT,
         "epsilon = 2 is outside (0, 1]"},
        {"a parameter pt does not declare", [](pb::JobSpec& s) { s.set_radius(3); },
         Code::INVALID_ARGUMENT, "unknown parameter 'radius' for pt (its parameters: width, "},
        {"a misspelled parameter",
         guided([](pb::JobSpec& s) { (*s.mutable_parameters())["radiuss"].set_real_value(3); }),
         Code::INVALID_ARGUMENT, "unknown parameter 'radiuss' for guided"},
        {"a parameter of the wrong type",
         guided([](pb::JobSpec& s) { (*s.mutable_parameters())["y"].set_real_value(2.5); }),
         Code::INVALID_ARGUMENT, "y must be a whole number, got 2.5"},
        {"text that is not a number",
         guided([](pb::JobSpec& s) { (*s.mutable_parameters())["radius"].set_text_value("x"); }),
         Code::INVALID_ARGUMENT, "radius must be a number, got 'x'"},
        {"a parameter given twice with two values", guided([](pb::JobSpec& s) {
             s.set_k(3);
             (*s.mutable_parameters())["k"].set_int_value(4);
         }),
         Code::INVALID_ARGUMENT, "parameter k is given twice with two values"},
        {"max depth 0", [](pb::JobSpec& s) { s.set_max_depth(0); }, Code::INVALID_ARGUMENT,
         "max_depth = 0 must be >= 1"},
        {"max depth over the limit", [](pb::JobSpec& s) { s.set_max_depth(65); },
         Code::RESOURCE_EXHAUSTED, "max_depth = 65 exceeds this server's limit of 64"},
        {"negative preview interval", [](pb::JobSpec& s) { s.set_preview_interval_seconds(-1); },
         Code::INVALID_ARGUMENT, "preview_interval = -1 must be >= 0"},
        {"tiny preview interval", [](pb::JobSpec& s) { s.set_preview_interval_seconds(0.001); },
         Code::INVALID_ARGUMENT, "preview_interval must be 0 (no previews) or at least 0.05 s"},
        {"negative type layers", [](pb::JobSpec& s) { s.set_max_type_layers(-1); },
         Code::INVALID_ARGUMENT, "layers = -1 is outside [0, 1024]"},
    };
    for (const Case& c : cases) {
        pb::JobSpec spec = sceneSpec("cornell", 16, 16, 1);
        c.change(spec);
        Submitted r = submit(*stub, spec);
        EXPECT_EQ(r.status.error_code(), c.code) << c.name << ": " << r.status.error_message();
        EXPECT_NE(r.status.error_message().find(c.message), std::string::npos)
            << c.name << ": '" << r.status.error_message() << "' lacks '" << c.message << "'";
    }
    // Nothing of that was queued, and the defaults (no budget, no size) are accepted.
    pb::JobSpec minimal;
    minimal.mutable_scene()->set_scene_name("cornell");
    minimal.set_width(16);
    minimal.set_height(16);
    Submitted ok = submit(*stub, minimal);
    ASSERT_TRUE(ok.status.ok()) << ok.status.error_message();
    pb::ListJobsResponse jobs;
    auto ctx = context();
    ASSERT_TRUE(stub->ListJobs(ctx.get(), {}, &jobs).ok());
    EXPECT_EQ(jobs.jobs_size(), 1);
    pb::Job end = waitForEnd(*stub, ok.id);
    EXPECT_EQ(end.state(), pb::JOB_STATE_DONE);
    EXPECT_EQ(end.stats().at("spp"), 16.0) << "the default budget: 16 in the native unit";

    pb::ListJobsRequest badStates;
    badStates.add_states(pb::JobState(99));
    ctx = context();
    EXPECT_EQ(stub->ListJobs(ctx.get(), badStates, &jobs).error_code(), Code::INVALID_ARGUMENT);
}

TEST(ServiceValidation, UnknownJobsAreNotFoundAndWrongStatesFailedPrecondition) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::Job job;
    pb::GetJobRequest get;
    get.set_job_id("nosuchjob");
    auto ctx = context();
    EXPECT_EQ(stub->GetJob(ctx.get(), get, &job).error_code(), Code::NOT_FOUND);
    pb::CancelJobRequest cancel;
    cancel.set_job_id("nosuchjob");
    ctx = context();
    EXPECT_EQ(stub->CancelJob(ctx.get(), cancel, &job).error_code(), Code::NOT_FOUND);
    pb::DeleteJobRequest del;
    del.set_job_id("nosuchjob");
    pb::DeleteJobResponse deleted;
    ctx = context();
    EXPECT_EQ(stub->DeleteJob(ctx.get(), del, &deleted).error_code(), Code::NOT_FOUND);
    EXPECT_EQ(watch(*stub, "nosuchjob").status.error_code(), Code::NOT_FOUND);
    EXPECT_EQ(fetch(*stub, "nosuchjob", pb::RESULT_KIND_EXR).status.error_code(), Code::NOT_FOUND);

    pb::JobSpec spec = sceneSpec("cornell", 96, 72, 1);
    spec.mutable_budget()->set_kind(pb::BUDGET_KIND_SECONDS);
    spec.mutable_budget()->set_amount(30);
    Submitted running = submit(*stub, spec);
    ASSERT_TRUE(running.status.ok());
    ASSERT_TRUE(waitForState(*stub, running.id, pb::JOB_STATE_RENDERING));
    Fetched early = fetch(*stub, running.id, pb::RESULT_KIND_EXR);
    EXPECT_EQ(early.status.error_code(), Code::FAILED_PRECONDITION);
    EXPECT_NE(early.status.error_message().find("RENDERING"), std::string::npos)
        << early.status.error_message();
    del.set_job_id(running.id);
    ctx = context();
    grpc::Status s = stub->DeleteJob(ctx.get(), del, &deleted);
    EXPECT_EQ(s.error_code(), Code::FAILED_PRECONDITION);
    EXPECT_NE(s.error_message().find("cancel it"), std::string::npos) << s.error_message();
    EXPECT_EQ(fetch(*stub, running.id, pb::RESULT_KIND_UNSPECIFIED).status.error_code(),
              Code::INVALID_ARGUMENT);
    cancel.set_job_id(running.id);
    ctx = context();
    ASSERT_TRUE(stub->CancelJob(ctx.get(), cancel, &job).ok());
    ASSERT_EQ(waitForEnd(*stub, running.id).state(), pb::JOB_STATE_CANCELLED);
    // Finished: deleting works now; cancelling a DONE job is the wrong state.
    ctx = context();
    EXPECT_TRUE(stub->DeleteJob(ctx.get(), del, &deleted).ok());

    Submitted small = submit(*stub, sceneSpec("cornell", 8, 8, 1));
    ASSERT_EQ(waitForEnd(*stub, small.id).state(), pb::JOB_STATE_DONE);
    cancel.set_job_id(small.id);
    ctx = context();
    EXPECT_EQ(stub->CancelJob(ctx.get(), cancel, &job).error_code(), Code::FAILED_PRECONDITION);
}

TEST(ServiceValidation, QueueAndWatcherLimitsAreResourceExhausted) {
    TempDir store;
    Daemon daemon(store.path(), {"--max-jobs", "1", "--max-queued", "2", "--max-watchers", "2"});
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::JobSpec spec = sceneSpec("cornell", 64, 48, 1);
    spec.mutable_budget()->set_kind(pb::BUDGET_KIND_SECONDS);
    spec.mutable_budget()->set_amount(30);
    Submitted running = submit(*stub, spec);
    ASSERT_TRUE(running.status.ok());
    ASSERT_TRUE(waitForState(*stub, running.id, pb::JOB_STATE_RENDERING));
    Submitted q1 = submit(*stub, spec), q2 = submit(*stub, spec), q3 = submit(*stub, spec);
    EXPECT_TRUE(q1.status.ok());
    EXPECT_TRUE(q2.status.ok());
    EXPECT_EQ(q3.status.error_code(), Code::RESOURCE_EXHAUSTED);
    EXPECT_NE(q3.status.error_message().find("queue is full"), std::string::npos)
        << q3.status.error_message();

    // Two watchers stay connected; the third is refused.
    std::vector<std::unique_ptr<grpc::ClientContext>> contexts;
    std::vector<std::unique_ptr<grpc::ClientReader<pb::JobEvent>>> readers;
    for (int i = 0; i < 2; ++i) {
        contexts.push_back(context());
        readers.push_back(stub->WatchJob(contexts.back().get(), watchRequest(running.id)));
        pb::JobEvent first;
        ASSERT_TRUE(readers.back()->Read(&first));  // joined: it got the state
    }
    WatchLog third = watch(*stub, running.id);
    EXPECT_EQ(third.status.error_code(), Code::RESOURCE_EXHAUSTED);
    EXPECT_NE(third.status.error_message().find("--max-watchers"), std::string::npos);
    for (auto& c : contexts) c->TryCancel();
    for (auto& r : readers) r->Finish();

    for (const auto& id : {q1.id, q2.id, running.id}) {
        pb::CancelJobRequest cancel;
        cancel.set_job_id(id);
        pb::Job job;
        auto ctx = context();
        EXPECT_TRUE(stub->CancelJob(ctx.get(), cancel, &job).ok());
    }
    EXPECT_EQ(waitForEnd(*stub, running.id).state(), pb::JOB_STATE_CANCELLED);
}

TEST(ServiceValidation, SceneThatFailsToLoadFailsTheJobNotTheDaemon) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::JobSpec garbage;
    garbage.mutable_scene()->set_glb("this is not a GLB file at all");
    pb::JobSpec badJson;
    badJson.mutable_scene()->mutable_gltf()->set_gltf("{ not json");
    pb::JobSpec badCamera = sceneSpec("cornell", 16, 16, 1);
    badCamera.set_camera("no-such-camera");
    for (const pb::JobSpec& spec : {garbage, badJson, badCamera}) {
        Submitted job = submit(*stub, spec);
        ASSERT_TRUE(job.status.ok()) << job.status.error_message();
        WatchLog log = watch(*stub, job.id);
        ASSERT_TRUE(log.status.ok());
        ASSERT_TRUE(log.last());
        EXPECT_EQ(log.last()->state(), pb::JOB_STATE_FAILED);
        EXPECT_FALSE(log.last()->error().empty());
        EXPECT_EQ(log.last()->error().find('\n'), std::string::npos)
            << "one line: " << log.last()->error();
        EXPECT_EQ(fetch(*stub, job.id, pb::RESULT_KIND_EXR).status.error_code(),
                  Code::FAILED_PRECONDITION);
    }
    // Still serving.
    Submitted ok = submit(*stub, sceneSpec("cornell", 16, 16, 1));
    EXPECT_EQ(waitForEnd(*stub, ok.id).state(), pb::JOB_STATE_DONE);
}

}  // namespace
}  // namespace partita::test
