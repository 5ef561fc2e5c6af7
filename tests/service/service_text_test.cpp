// Hostile text: bytes that are not UTF-8 in an upload or a request, and huge inputs echoed in
// messages. No stored or echoed text may make a response that clients cannot parse.
#include <gtest/gtest.h>

#include "service_client.h"

namespace partita::test {
namespace {

using namespace std::chrono_literals;

pb::JobSpec nonUtf8Upload() {
    pb::JobSpec spec;
    // A .gltf that starts with a byte that is not UTF-8: the loader's error quotes it.
    spec.mutable_scene()->mutable_gltf()->set_gltf("\xff\xfe{\"asset\":{\"version\":\"2.0\"}}");
    spec.set_width(16);
    spec.set_height(16);
    return spec;
}

grpc::Status listJobs(pb::Partita::Stub& stub, pb::ListJobsResponse& out) {
    auto ctx = context(20s);
    return stub.ListJobs(ctx.get(), pb::ListJobsRequest{}, &out);
}

TEST(ServiceText, NonUtf8InAFailedUploadDoesNotBreakListingForAnyone) {
    TempDir store;
    std::string id;
    {
        Daemon daemon(store.path());
        ASSERT_TRUE(daemon.running());
        auto stub = daemon.stub();
        Submitted job = submit(*stub, nonUtf8Upload());
        ASSERT_TRUE(job.status.ok()) << job.status.error_message();
        id = job.id;
        pb::Job end = waitForEnd(*stub, id, 30s);
        ASSERT_EQ(end.state(), pb::JOB_STATE_FAILED) << "GetJob must parse: " << end.DebugString();
        EXPECT_FALSE(end.error().empty());

        pb::ListJobsResponse list;
        grpc::Status s = listJobs(*stub, list);
        ASSERT_TRUE(s.ok()) << s.error_message();
        ASSERT_EQ(list.jobs_size(), 1);
        EXPECT_EQ(list.jobs(0).error(), end.error());
        WatchLog log = watch(*stub, id);
        EXPECT_TRUE(log.status.ok()) << log.status.error_message();
        EXPECT_EQ(log.states(), std::vector<pb::JobState>{pb::JOB_STATE_FAILED});
        EXPECT_EQ(daemon.stop(), 0);
    }
    // The stored record reads back as valid UTF-8 after a restart too.
    Daemon again(store.path());
    ASSERT_TRUE(again.running());
    auto stub = again.stub();
    pb::ListJobsResponse list;
    grpc::Status s = listJobs(*stub, list);
    ASSERT_TRUE(s.ok()) << s.error_message();
    ASSERT_EQ(list.jobs_size(), 1);
    EXPECT_EQ(list.jobs(0).id(), id);
}

TEST(ServiceText, NonUtf8RequestStringIsInvalidArgumentNamingTheField) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();

    pb::GetJobRequest get;
    get.set_job_id("ab\xc3\x28");
    pb::Job job;
    auto ctx = context(10s);
    grpc::Status s = stub->GetJob(ctx.get(), get, &job);
    EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << s.error_message();
    EXPECT_NE(s.error_message().find("job_id"), std::string::npos) << s.error_message();
    EXPECT_NE(s.error_message().find("UTF-8"), std::string::npos) << s.error_message();

    pb::JobSpec spec = sceneSpec("cornell", 16, 16, 1);
    spec.set_label("label \xff");
    Submitted bad = submit(*stub, spec);
    EXPECT_EQ(bad.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_NE(bad.status.error_message().find("spec.label"), std::string::npos)
        << bad.status.error_message();

    pb::JobSpec named = sceneSpec("corn\xe9ll", 16, 16, 1);
    bad = submit(*stub, named);
    EXPECT_EQ(bad.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_NE(bad.status.error_message().find("spec.scene.scene_name"), std::string::npos)
        << bad.status.error_message();

    auto wctx = context(10s);
    auto reader = stub->WatchJob(wctx.get(), watchRequest("\x80"));
    pb::JobEvent event;
    while (reader->Read(&event)) {
    }
    s = reader->Finish();
    EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << s.error_message();

    // The daemon still serves.
    EXPECT_TRUE(submit(*stub, sceneSpec("cornell", 16, 16, 1)).status.ok());
}

TEST(ServiceText, HugeInputsAreQuotedAsAShortPrefix) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();

    pb::GetJobRequest get;
    get.set_job_id(std::string(1 << 20, 'x'));
    pb::Job job;
    auto ctx = context(20s);
    grpc::Status s = stub->GetJob(ctx.get(), get, &job);
    EXPECT_EQ(s.error_code(), grpc::StatusCode::NOT_FOUND) << s.error_message().substr(0, 200);
    EXPECT_LT(s.error_message().size(), 200u);
    EXPECT_NE(s.error_message().find("1048576 bytes"), std::string::npos) << s.error_message();

    pb::JobSpec spec = sceneSpec("cornell", 16, 16, 1);
    spec.set_algorithm(std::string(5000, 'a'));
    Submitted bad = submit(*stub, spec);
    EXPECT_EQ(bad.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_LT(bad.status.error_message().size(), 400u) << bad.status.error_message();
    EXPECT_NE(bad.status.error_message().find("(this server has: "), std::string::npos);

    pb::JobSpec scene = sceneSpec(std::string(150, 's'), 16, 16, 1);
    bad = submit(*stub, scene);
    EXPECT_EQ(bad.status.error_code(), grpc::StatusCode::NOT_FOUND);
    EXPECT_EQ(bad.status.error_message().find(std::string(100, 's')), std::string::npos)
        << bad.status.error_message();
}

}  // namespace
}  // namespace partita::test
