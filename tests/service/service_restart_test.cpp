// Jobs are never lost: SIGTERM re-queues the running job and exits 0; after SIGKILL the running
// job is re-queued at the next start; finished results stay fetchable and queued jobs run.
#include <gtest/gtest.h>

#include "in_process.h"
#include "service_client.h"

namespace partita::test {
namespace {

using namespace std::chrono_literals;

const fs::path kScenes = PARTITA_SCENES_DIR;

/// A job of a few seconds here, deterministic (a sample budget): signals land while it renders.
pb::JobSpec restartJob() {
    return sceneSpec("cornell", 128, 96, 128, 9);
}

void interruptAndResume(int signal) {
    TempDir store;
    std::string id;
    {
        Daemon first(store.path());
        ASSERT_TRUE(first.running());
        auto stub = first.stub();
        Submitted job = submit(*stub, restartJob());
        ASSERT_TRUE(job.status.ok());
        id = job.id;
        ASSERT_TRUE(waitForState(*stub, id, pb::JOB_STATE_RENDERING));
        std::this_thread::sleep_for(100ms);
        int code = first.stop(signal);
        if (signal == SIGTERM) {
            EXPECT_EQ(code, 0) << first.log();
            EXPECT_NE(first.log().find("re-queued"), std::string::npos) << first.log();
        } else {
            EXPECT_EQ(code, 128 + SIGKILL);
        }
    }
    Daemon second(store.path());
    ASSERT_TRUE(second.running());
    auto stub = second.stub();
    pb::Job end = waitForEnd(*stub, id);
    ASSERT_EQ(end.state(), pb::JOB_STATE_DONE) << end.error() << "\n" << second.log();
    EXPECT_EQ(end.stats().at("requeued"), 1.0);
    if (signal == SIGKILL) {
        EXPECT_NE(second.log().find("re-queued after restart"), std::string::npos) << second.log();
    }
    EXPECT_TRUE(end.error().empty()) << "the re-queue note is cleared when it runs again";
    Fetched exr = fetch(*stub, id, pb::RESULT_KIND_EXR);
    ASSERT_TRUE(exr.status.ok());
    LayeredImage result = readExrBytes(exr.bytes);
    EXPECT_EQ(result.combined.width, 128);
    if (signal == SIGKILL) {
        // It rendered again from scratch: the same image as in-process.
        EXPECT_EQ(compareImages(result, renderInProcess(kScenes / "cornell" / "cornell.gltf", 128,
                                                        96, 128, 9)),
                  "");
    }
}

TEST(ServiceRestart, SigtermRequeuesTheRunningJobWhichCompletesAfterRestart) {
    interruptAndResume(SIGTERM);
}

TEST(ServiceRestart, SigkillMidJobThenRestartRequeuesAndCompletesIt) {
    interruptAndResume(SIGKILL);
}

TEST(ServiceRestart, FinishedResultsStayAndQueuedJobsRunAfterRestart) {
    TempDir store;
    std::string done, running, queued, uploaded, cancelled;
    std::string doneExr;
    {
        Daemon first(store.path(), {"--max-jobs", "1"});
        ASSERT_TRUE(first.running());
        auto stub = first.stub();
        Submitted a = submit(*stub, sceneSpec("cornell", 24, 16, 2, 1));
        ASSERT_TRUE(a.status.ok());
        ASSERT_EQ(waitForEnd(*stub, a.id).state(), pb::JOB_STATE_DONE);
        done = a.id;
        doneExr = fetch(*stub, done, pb::RESULT_KIND_EXR).bytes;
        ASSERT_FALSE(doneExr.empty());

        Submitted b = submit(*stub, restartJob());
        ASSERT_TRUE(b.status.ok());
        running = b.id;
        ASSERT_TRUE(waitForState(*stub, running, pb::JOB_STATE_RENDERING));
        // Queued behind it: a named scene, an upload (its bytes must survive too), a cancelled one.
        Submitted c = submit(*stub, sceneSpec("cornell-glass", 24, 16, 2, 1));
        pb::JobSpec upload;
        upload.mutable_scene()->set_glb(makeGridGlb(16));
        upload.set_width(16);
        upload.set_height(16);
        Submitted d = submit(*stub, upload);
        Submitted e = submit(*stub, sceneSpec("cornell", 16, 16, 1, 1));
        ASSERT_TRUE(c.status.ok() && d.status.ok() && e.status.ok());
        queued = c.id;
        uploaded = d.id;
        cancelled = e.id;
        pb::CancelJobRequest cancel;
        cancel.set_job_id(cancelled);
        pb::Job ignored;
        auto ctx = context();
        ASSERT_TRUE(stub->CancelJob(ctx.get(), cancel, &ignored).ok());
        EXPECT_EQ(first.stop(SIGTERM), 0) << first.log();
    }
    Daemon second(store.path(), {"--max-jobs", "1"});
    ASSERT_TRUE(second.running());
    auto stub = second.stub();
    // The finished job: same state, same bytes, and a late watcher still gets its final frame.
    Fetched again = fetch(*stub, done, pb::RESULT_KIND_EXR);
    ASSERT_TRUE(again.status.ok());
    EXPECT_EQ(again.bytes, doneExr);
    WatchLog log = watch(*stub, done, true, true);
    ASSERT_TRUE(log.status.ok());
    ASSERT_EQ(log.frames().size(), 1u);
    EXPECT_TRUE(log.frames()[0]->final());
    EXPECT_EQ(compareImages(frameImage(*log.frames()[0]), readExrBytes(doneExr)), "");
    for (const auto& id : {running, queued, uploaded}) {
        pb::Job end = waitForEnd(*stub, id);
        EXPECT_EQ(end.state(), pb::JOB_STATE_DONE) << id << ": " << end.error();
    }
    EXPECT_EQ(waitForEnd(*stub, cancelled).state(), pb::JOB_STATE_CANCELLED);
}

TEST(ServiceRestart, SigintAlsoStopsCleanlyAndRemovesThePortFile) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    EXPECT_EQ(daemon.stop(SIGINT), 0) << daemon.log();
    EXPECT_NE(daemon.log().find("stopped"), std::string::npos);
    // The same store opens again at once (the lock is released).
    Daemon again(store.path());
    EXPECT_TRUE(again.running());
}

TEST(ServiceRestart, SecondDaemonOnTheSameStoreIsRefused) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto [code, log] = runPartitad({"--listen", "127.0.0.1:0", "--store", store.path().string()});
    EXPECT_NE(code, 0);
    EXPECT_NE(log.find("in use by another partitad"), std::string::npos) << log;
}

}  // namespace
}  // namespace partita::test
