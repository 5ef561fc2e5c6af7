// Cancelling a job in each phase: while queued (at once), while loading (between the loading
// steps), while rendering (the core polls the cancel flag).
#include <gtest/gtest.h>

#include <future>
#include <thread>

#include "service_client.h"

namespace partita::test {
namespace {

using namespace std::chrono_literals;

pb::Job cancelJob(pb::Partita::Stub& stub, const std::string& id, grpc::Status* status = nullptr) {
    pb::CancelJobRequest request;
    request.set_job_id(id);
    pb::Job job;
    auto ctx = context();
    grpc::Status s = stub.CancelJob(ctx.get(), request, &job);
    if (status) *status = s;
    EXPECT_TRUE(s.ok()) << s.error_message();
    return job;
}

pb::JobSpec longJob() {
    pb::JobSpec spec = sceneSpec("cornell", 160, 120, 1);
    spec.mutable_budget()->set_kind(pb::BUDGET_KIND_SECONDS);
    spec.mutable_budget()->set_amount(60);
    spec.set_preview_interval_seconds(0.2);
    return spec;
}

TEST(ServiceCancel, WhileQueuedIsImmediate) {
    TempDir store;
    Daemon daemon(store.path(), {"--max-jobs", "1"});
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    Submitted running = submit(*stub, longJob());
    ASSERT_TRUE(running.status.ok());
    ASSERT_TRUE(waitForState(*stub, running.id, pb::JOB_STATE_RENDERING));
    Submitted queued = submit(*stub, sceneSpec("cornell", 16, 16, 1));
    ASSERT_TRUE(queued.status.ok());

    pb::Job cancelled = cancelJob(*stub, queued.id);
    EXPECT_EQ(cancelled.state(), pb::JOB_STATE_CANCELLED) << "a queued job is cancelled at once";
    WatchLog log = watch(*stub, queued.id);
    EXPECT_TRUE(log.status.ok());
    EXPECT_EQ(log.states(), std::vector<pb::JobState>{pb::JOB_STATE_CANCELLED});
    // Cancelling again is harmless.
    EXPECT_EQ(cancelJob(*stub, queued.id).state(), pb::JOB_STATE_CANCELLED);

    auto start = std::chrono::steady_clock::now();
    cancelJob(*stub, running.id);
    EXPECT_EQ(waitForEnd(*stub, running.id, 10s).state(), pb::JOB_STATE_CANCELLED);
    EXPECT_LT(std::chrono::steady_clock::now() - start, 3s);
    EXPECT_EQ(fetch(*stub, running.id, pb::RESULT_KIND_EXR).status.error_code(),
              grpc::StatusCode::FAILED_PRECONDITION);
}

TEST(ServiceCancel, WhileLoadingABigUploadedScene) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::SceneSource scene;
    scene.set_glb(makeGridGlb(900));  // 1.6 M triangles, ~25 MB: streamed (over 4 MiB)
    Uploaded uploaded = upload(*stub, scene);
    ASSERT_TRUE(uploaded.status.ok()) << uploaded.status.error_message();
    pb::JobSpec spec;
    spec.mutable_scene()->set_upload_id(uploaded.id);
    spec.set_width(32);
    spec.set_height(24);
    Submitted job = submit(*stub, spec);
    ASSERT_TRUE(job.status.ok()) << job.status.error_message();
    auto watcher = std::async(std::launch::async, [&] { return watch(*stub, job.id); });
    ASSERT_TRUE(waitForState(*stub, job.id, pb::JOB_STATE_LOADING, 20s));
    auto start = std::chrono::steady_clock::now();
    cancelJob(*stub, job.id);
    pb::Job end = waitForEnd(*stub, job.id, 30s);
    EXPECT_EQ(end.state(), pb::JOB_STATE_CANCELLED) << end.error();
    WatchLog log = watcher.get();
    EXPECT_TRUE(log.status.ok());
    std::vector<pb::JobState> states = log.states();
    EXPECT_EQ(std::find(states.begin(), states.end(), pb::JOB_STATE_RENDERING), states.end())
        << "cancelled while loading: it must never render";
    ASSERT_FALSE(states.empty());
    EXPECT_EQ(states.back(), pb::JOB_STATE_CANCELLED);
    std::printf("cancel while loading took %.2f s\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

TEST(ServiceCancel, WhileRendering) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    Submitted job = submit(*stub, longJob());
    ASSERT_TRUE(job.status.ok());
    auto ctx = context();
    auto reader = stub->WatchJob(ctx.get(), watchRequest(job.id, true));
    pb::JobEvent event;
    bool sawProgress = false, sawFrame = false;
    while (!(sawProgress && sawFrame) && reader->Read(&event)) {
        sawProgress |= event.has_progress() && event.progress().phase() == "render";
        sawFrame |= event.has_preview();
    }
    ASSERT_TRUE(sawProgress && sawFrame);
    auto start = std::chrono::steady_clock::now();
    cancelJob(*stub, job.id);
    std::vector<pb::JobState> states;
    while (reader->Read(&event))
        if (event.has_state()) states.push_back(event.state().state());
    EXPECT_TRUE(reader->Finish().ok());
    EXPECT_LT(std::chrono::steady_clock::now() - start, 3s) << "the render polls the cancel flag";
    EXPECT_EQ(states, std::vector<pb::JobState>{pb::JOB_STATE_CANCELLED});
    EXPECT_EQ(waitForEnd(*stub, job.id).state(), pb::JOB_STATE_CANCELLED);
}

}  // namespace
}  // namespace partita::test
