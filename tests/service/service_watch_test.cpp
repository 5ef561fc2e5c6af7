// Watching: a watcher that disconnects changes nothing for the job or other watchers; a late
// watcher first gets the state and the latest frame; a slow watcher skips frames, never the final.
#include <gtest/gtest.h>

#include <future>
#include <thread>

#include "in_process.h"
#include "service_client.h"

namespace partita::test {
namespace {

using namespace std::chrono_literals;

TEST(ServiceWatch, DisconnectingWatcherChangesNothingForOthers) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::JobSpec spec = sceneSpec("cornell", 160, 120, 64, 2);
    spec.set_preview_interval_seconds(0.1);
    Submitted job = submit(*stub, spec);
    ASSERT_TRUE(job.status.ok());

    // The steady watcher, on its own connection, watches to the end.
    auto otherStub = daemon.stub();
    auto steady =
        std::async(std::launch::async, [&] { return watch(*otherStub, job.id, true, true); });

    // The leaving watcher reads a few events, then its client goes away mid-stream.
    auto ctx = context();
    auto reader = stub->WatchJob(ctx.get(), watchRequest(job.id, true, true));
    pb::JobEvent event;
    int frames = 0;
    while (frames < 2 && reader->Read(&event)) frames += event.has_preview();
    ASSERT_EQ(frames, 2);
    ctx->TryCancel();
    while (reader->Read(&event)) {
    }
    EXPECT_EQ(reader->Finish().error_code(), grpc::StatusCode::CANCELLED);

    // A late watcher: the state first, then the latest frame.
    {
        pb::WatchJobRequest late;
        late.set_job_id(job.id);
        late.set_previews(true);
        auto lateCtx = context();
        auto lateReader = stub->WatchJob(lateCtx.get(), late);
        pb::JobEvent first, second;
        ASSERT_TRUE(lateReader->Read(&first));
        EXPECT_TRUE(first.has_state());
        ASSERT_TRUE(lateReader->Read(&second));
        EXPECT_TRUE(second.has_preview())
            << "a late watcher gets the latest frame right after the state";
        lateCtx->TryCancel();
        while (lateReader->Read(&event)) {
        }
        lateReader->Finish();
    }

    WatchLog log = steady.get();
    ASSERT_TRUE(log.status.ok()) << log.status.error_message();
    ASSERT_TRUE(log.last());
    EXPECT_EQ(log.last()->state(), pb::JOB_STATE_DONE);
    ASSERT_FALSE(log.frames().empty());
    EXPECT_TRUE(log.frames().back()->final());
    Fetched exr = fetch(*stub, job.id, pb::RESULT_KIND_EXR);
    EXPECT_EQ(compareImages(frameImage(*log.frames().back()), readExrBytes(exr.bytes)), "");

    // The daemon still serves and the job is unaffected.
    EXPECT_EQ(waitForEnd(*stub, job.id).state(), pb::JOB_STATE_DONE);
}

TEST(ServiceWatch, SlowWatcherSkipsFramesButGetsTheFinalOneAndTheEnd) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    // Big raw frames (~30 layers of 230 KB) fill the stream's flow-control window at once. The
    // previews are spaced by ten times their cost (preview_schedule.h, ~20-40 ms a frame of 30
    // PNGs here): enough samples for several of them.
    pb::JobSpec spec = sceneSpec("cornell-glass", 160, 120, 128, 4);
    spec.set_preview_interval_seconds(0.05);
    Submitted job = submit(*stub, spec);
    ASSERT_TRUE(job.status.ok());

    auto fastStub = daemon.stub();
    auto fast =
        std::async(std::launch::async, [&] { return watch(*fastStub, job.id, true, false); });

    // The slow client reads one event, then nothing until the job has finished.
    auto ctx = context(120s);
    auto reader = stub->WatchJob(ctx.get(), watchRequest(job.id, true, true));
    pb::JobEvent event;
    ASSERT_TRUE(reader->Read(&event));
    auto started = std::chrono::steady_clock::now();
    ASSERT_EQ(waitForEnd(*daemon.stub(), job.id).state(), pb::JOB_STATE_DONE)
        << "a stalled watcher must not hold the render back";
    double stalled =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    std::vector<uint64_t> sequences;
    bool finalSeen = false;
    pb::JobState lastState = pb::JOB_STATE_UNSPECIFIED;
    while (reader->Read(&event)) {
        if (event.has_preview()) {
            sequences.push_back(event.preview().sequence());
            finalSeen |= event.preview().final();
        }
        if (event.has_state()) lastState = event.state().state();
    }
    ASSERT_TRUE(reader->Finish().ok());
    EXPECT_TRUE(finalSeen);
    EXPECT_EQ(lastState, pb::JOB_STATE_DONE);
    WatchLog fastLog = fast.get();
    ASSERT_TRUE(fastLog.status.ok());
    ASSERT_FALSE(fastLog.frames().empty());
    uint64_t produced = fastLog.frames().back()->sequence();
    ASSERT_GE(produced, 4u) << "the job should have produced several previews";
    EXPECT_LT(sequences.size(), produced) << "the slow watcher should have skipped frames";
    ASSERT_FALSE(sequences.empty());
    EXPECT_EQ(sequences.back(), produced) << "both end with the same final frame";
    EXPECT_TRUE(std::is_sorted(sequences.begin(), sequences.end()));
    std::printf("slow watcher: %zu of %llu frames; the job ran %.2f s while it was stalled\n",
                sequences.size(), static_cast<unsigned long long>(produced), stalled);
}

}  // namespace
}  // namespace partita::test
