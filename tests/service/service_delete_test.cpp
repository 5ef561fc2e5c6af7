// Cancel then delete at once: the delete of a job whose cancel was requested succeeds, whether
// or not its render has stopped yet; its record and files go when it stops.
#include <gtest/gtest.h>

#include <thread>

#include "service_client.h"

namespace partita::test {
namespace {

using namespace std::chrono_literals;

TEST(ServiceDelete, DeleteRightAfterCancelOfARenderingJobSucceeds) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::JobSpec spec = sceneSpec("cornell", 160, 120, 1);
    spec.mutable_budget()->set_kind(pb::BUDGET_KIND_SECONDS);
    spec.mutable_budget()->set_amount(60);
    Submitted job = submit(*stub, spec);
    ASSERT_TRUE(job.status.ok());
    ASSERT_TRUE(waitForState(*stub, job.id, pb::JOB_STATE_RENDERING, 30s));

    // Deleting a job that renders and was not cancelled is still refused.
    pb::DeleteJobRequest del;
    del.set_job_id(job.id);
    pb::DeleteJobResponse deleted;
    auto d0 = context(10s);
    EXPECT_EQ(stub->DeleteJob(d0.get(), del, &deleted).error_code(),
              grpc::StatusCode::FAILED_PRECONDITION);

    pb::CancelJobRequest cancel;
    cancel.set_job_id(job.id);
    pb::Job after;
    auto c = context(10s);
    ASSERT_TRUE(stub->CancelJob(c.get(), cancel, &after).ok());
    auto d1 = context(10s);
    grpc::Status s = stub->DeleteJob(d1.get(), del, &deleted);
    EXPECT_TRUE(s.ok()) << s.error_message();

    pb::GetJobRequest get;
    get.set_job_id(job.id);
    auto g = context(10s);
    EXPECT_EQ(stub->GetJob(g.get(), get, &after).error_code(), grpc::StatusCode::NOT_FOUND);
    const fs::path folder = store.path() / "jobs" / job.id;
    for (int i = 0; i < 200 && fs::exists(folder); ++i) std::this_thread::sleep_for(50ms);
    EXPECT_FALSE(fs::exists(folder)) << "the job's folder is removed once the render stops";

    // After a restart the job stays deleted.
    EXPECT_EQ(daemon.stop(), 0);
    Daemon again(store.path());
    ASSERT_TRUE(again.running());
    auto stub2 = again.stub();
    pb::ListJobsResponse list;
    auto l = context(10s);
    ASSERT_TRUE(stub2->ListJobs(l.get(), pb::ListJobsRequest{}, &list).ok());
    EXPECT_EQ(list.jobs_size(), 0);
}

}  // namespace
}  // namespace partita::test
