// The queue: higher priority first, then submission order; several jobs render at once on the
// shared pool; an upload is dropped from the store once its job has finished.
#include <gtest/gtest.h>

#include <thread>

#include "service_client.h"

namespace partita::test {
namespace {

using namespace std::chrono_literals;

pb::Job getJob(pb::Partita::Stub& stub, const std::string& id) {
    pb::GetJobRequest request;
    request.set_job_id(id);
    pb::Job job;
    auto ctx = context();
    EXPECT_TRUE(stub.GetJob(ctx.get(), request, &job).ok());
    return job;
}

TEST(ServiceQueue, HigherPriorityRunsFirstThenSubmissionOrder) {
    TempDir store;
    Daemon daemon(store.path(), {"--max-jobs", "1"});
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::JobSpec blocker = sceneSpec("cornell", 64, 48, 1);
    blocker.mutable_budget()->set_kind(pb::BUDGET_KIND_SECONDS);
    blocker.mutable_budget()->set_amount(30);
    Submitted first = submit(*stub, blocker);
    ASSERT_TRUE(first.status.ok());
    ASSERT_TRUE(waitForState(*stub, first.id, pb::JOB_STATE_RENDERING));

    std::vector<std::pair<int, std::string>> submitted;  // priority, id
    for (int priority : {0, 5, 0, 5, -1}) {
        pb::JobSpec spec = sceneSpec("cornell", 8, 8, 1);
        spec.set_priority(priority);
        Submitted s = submit(*stub, spec);
        ASSERT_TRUE(s.status.ok());
        submitted.push_back({priority, s.id});
    }
    pb::CancelJobRequest cancel;
    cancel.set_job_id(first.id);
    pb::Job ignored;
    auto ctx = context();
    ASSERT_TRUE(stub->CancelJob(ctx.get(), cancel, &ignored).ok());

    std::vector<std::pair<int64_t, std::string>> starts;
    for (const auto& [priority, id] : submitted) {
        pb::Job end = waitForEnd(*stub, id);
        ASSERT_EQ(end.state(), pb::JOB_STATE_DONE);
        starts.push_back({end.started_unix_ms(), id});
    }
    std::stable_sort(starts.begin(), starts.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::string> order,
        expected = {submitted[1].second, submitted[3].second, submitted[0].second,
                    submitted[2].second, submitted[4].second};
    for (const auto& s : starts) order.push_back(s.second);
    EXPECT_EQ(order, expected);
}

TEST(ServiceQueue, JobsRenderConcurrentlyAndUploadsAreDroppedWhenDone) {
    TempDir store;
    Daemon daemon(store.path(), {"--max-jobs", "3"});
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    std::vector<std::string> ids;
    for (int i = 0; i < 3; ++i) {
        pb::JobSpec spec;
        spec.mutable_scene()->set_glb(makeGridGlb(30));
        spec.set_width(48);
        spec.set_height(48);
        spec.mutable_budget()->set_kind(pb::BUDGET_KIND_SECONDS);
        spec.mutable_budget()->set_amount(1.5);
        Submitted s = submit(*stub, spec);
        ASSERT_TRUE(s.status.ok());
        ids.push_back(s.id);
        EXPECT_TRUE(fs::exists(store.path() / "jobs" / s.id / "scene.upload"));
    }
    // All three render at the same time on the shared pool.
    auto deadline = std::chrono::steady_clock::now() + 10s;
    bool allRendering = false;
    while (!allRendering && std::chrono::steady_clock::now() < deadline) {
        allRendering = true;
        for (const auto& id : ids)
            allRendering &= getJob(*stub, id).state() == pb::JOB_STATE_RENDERING;
    }
    EXPECT_TRUE(allRendering);
    for (const auto& id : ids) {
        EXPECT_EQ(waitForEnd(*stub, id).state(), pb::JOB_STATE_DONE);
        // Dropped right after the DONE transition is recorded (never before: a crash in between
        // must leave a re-queued job its scene).
        fs::path upload = store.path() / "jobs" / id / "scene.upload";
        for (int i = 0; i < 200 && fs::exists(upload); ++i) std::this_thread::sleep_for(10ms);
        EXPECT_FALSE(fs::exists(upload));
        EXPECT_TRUE(fs::exists(store.path() / "jobs" / id / "result.exr"));
    }
}

}  // namespace
}  // namespace partita::test
