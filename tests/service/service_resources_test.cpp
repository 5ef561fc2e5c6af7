// Resource limits a hostile or careless client must not get around: a job's memory estimate,
// the memory of the running jobs together, watchers of any job, the store's size.
#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>
#include <thread>

#include "service_client.h"

namespace partita::test {
namespace {

using namespace std::chrono_literals;

TEST(ServiceResources, JobOverTheMemoryLimitIsRefusedWithItsEstimateOneUnderRuns) {
    TempDir store;
    Daemon daemon(store.path(), {"--max-job-memory", "64"});
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    EXPECT_EQ(serverInfo(*stub).limits().max_job_memory_bytes(), int64_t(64) << 20);

    // 2048x2048 with the default 32 type layers: ~3.6 GiB by the estimate.
    Submitted big = submit(*stub, sceneSpec("cornell", 2048, 2048, 1));
    EXPECT_EQ(big.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    const std::string& why = big.status.error_message();
    EXPECT_NE(why.find("estimated"), std::string::npos) << why;
    EXPECT_NE(why.find("GiB"), std::string::npos) << why;
    EXPECT_NE(why.find("--max-job-memory"), std::string::npos) << why;

    // 1024 type layers at a modest size: refused too (the layers, not the pixels, cost).
    pb::JobSpec layers = sceneSpec("cornell", 320, 240, 1);
    layers.set_max_type_layers(1024);
    EXPECT_EQ(submit(*stub, layers).status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);

    Submitted small = submit(*stub, sceneSpec("cornell", 64, 48, 1));
    ASSERT_TRUE(small.status.ok()) << small.status.error_message();
    EXPECT_EQ(waitForEnd(*stub, small.id, 60s).state(), pb::JOB_STATE_DONE);
}

TEST(ServiceResources, MltEstimateCountsItsBootstrapAndChains) {
    TempDir store;
    Daemon daemon(store.path(), {"--max-job-memory", "64"});
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    // 16x12: pt is estimated at ~8 MiB, mlt with a time budget at ~66 MiB, for whatever size:
    // its bootstrap's candidates (the start-up rule's 100000 samples for a time budget, of ~14
    // candidates of 40 B: ~53 MiB) and its 256 chains' states (4 MiB; their splats go straight
    // into the film).
    Submitted pt = submit(*stub, sceneSpec("cornell", 16, 12, 1));
    ASSERT_TRUE(pt.status.ok()) << pt.status.error_message();
    pb::JobSpec mlt = sceneSpec("cornell", 16, 12, 4);
    mlt.set_algorithm("mlt");
    mlt.mutable_budget()->set_kind(pb::BUDGET_KIND_SECONDS);
    Submitted refused = submit(*stub, mlt);
    EXPECT_EQ(refused.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    const std::string& why = refused.status.error_message();
    // The chains' film, the odd half's, the direct light's film and its error estimate's two
    // images (direct per-pixel).
    EXPECT_NE(why.find("4 films"), std::string::npos) << "mlt's four films\n" << why;
    EXPECT_NE(why.find("mlt bootstrap 53.4 MiB"), std::string::npos) << why;
    EXPECT_NE(why.find("chains 4.0 MiB"), std::string::npos) << why;
    EXPECT_EQ(waitForEnd(*stub, pt.id, 60s).state(), pb::JOB_STATE_DONE);

    // Its film keeps at most `layers` + 1 type buffers (issue #24): the estimate does not grow
    // with the budget (it did, when every type that occurred had a buffer).
    pb::JobSpec more = mlt;
    more.mutable_budget()->set_amount(4096);
    Submitted big = submit(*stub, more);
    EXPECT_EQ(big.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_EQ(big.status.error_message(), refused.status.error_message());

    // A small mutation budget gets a small bootstrap by the start-up rule (4096 samples, the
    // rule's least: ~2.2 MiB of candidates), and fits.
    pb::JobSpec small = mlt;
    small.mutable_budget()->set_kind(pb::BUDGET_KIND_MUTATIONS_PER_PIXEL);
    Submitted fits = submit(*stub, small);
    ASSERT_TRUE(fits.status.ok()) << fits.status.error_message();
    EXPECT_EQ(waitForEnd(*stub, fits.id, 60s).state(), pb::JOB_STATE_DONE);
    EXPECT_NE(why.find("(33 type buffers)"), std::string::npos) << why;
}

TEST(ServiceResources, PartitionedEstimateCountsItsFilmsPrepassAndChains) {
    TempDir store;
    Daemon daemon(store.path(), {"--max-job-memory", "32"});
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    // 16x12, K = 10, a time budget: ~37 MiB by the estimate: 22 films (K and the complement,
    // each its chains' and its odd chains' for the error estimate),
    // the pre-pass's half-B records (the start-up rule's 100000 samples for a time budget:
    // 50000 of ~13 records of 40 B: 24.8 MiB) and the 256 chains' states as for mlt (4 MiB).
    // Every partition with chains (the paper's estimators; auto's per-pixel part below).
    pb::JobSpec spec = sceneSpec("cornell", 16, 12, 4);
    spec.set_algorithm("partitioned");
    spec.mutable_budget()->set_kind(pb::BUDGET_KIND_SECONDS);
    spec.set_k(10);
    (*spec.mutable_parameters())["estimators"].set_text_value("chains");
    Submitted refused = submit(*stub, spec);
    EXPECT_EQ(refused.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    const std::string& why = refused.status.error_message();
    EXPECT_NE(why.find("22 films"), std::string::npos)
        << "two films per partition (its chains' and its odd chains')\n"
        << why;
    EXPECT_NE(why.find("11 partitions"), std::string::npos) << why;
    EXPECT_NE(why.find("pre-pass records 24.8 MiB"), std::string::npos) << why;
    EXPECT_NE(why.find("chains 4.0 MiB"), std::string::npos) << why;
    EXPECT_NE(why.find("(0 type buffers)"), std::string::npos) << "partition films\n" << why;

    // A smaller pre-pass (4000 samples: 1015.6 KiB of records) fits, and runs.
    spec.set_bootstrap_samples(4000);
    spec.mutable_budget()->set_kind(pb::BUDGET_KIND_MUTATIONS_PER_PIXEL);
    Submitted small = submit(*stub, spec);
    ASSERT_TRUE(small.status.ok()) << small.status.error_message();
    EXPECT_EQ(waitForEnd(*stub, small.id, 60s).state(), pb::JOB_STATE_DONE);

    // With estimators=auto (the default), also the pilots and the per-pixel partitions (the
    // direct light's among them): its film, and bdpt's splats, the estimator it may be.
    (*spec.mutable_parameters())["estimators"].set_text_value("auto");
    Submitted chosen = submit(*stub, spec);
    EXPECT_EQ(chosen.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_NE(chosen.status.error_message().find("12 partitions"), std::string::npos)
        << chosen.status.error_message();
    EXPECT_NE(chosen.status.error_message().find("pilots and per-pixel partitions"),
              std::string::npos)
        << chosen.status.error_message();

    // So does mlt's bootstrap: 4000 samples instead of 100000 bring it under 32 MiB too.
    pb::JobSpec mlt = sceneSpec("cornell", 16, 12, 4);
    mlt.set_algorithm("mlt");
    mlt.mutable_budget()->set_kind(pb::BUDGET_KIND_SECONDS);
    EXPECT_EQ(submit(*stub, mlt).status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    mlt.set_bootstrap_samples(4000);
    mlt.mutable_budget()->set_kind(pb::BUDGET_KIND_MUTATIONS_PER_PIXEL);
    Submitted mltSmall = submit(*stub, mlt);
    ASSERT_TRUE(mltSmall.status.ok()) << mltSmall.status.error_message();
    EXPECT_EQ(waitForEnd(*stub, mltSmall.id, 60s).state(), pb::JOB_STATE_DONE);
}

/// The memory estimate the daemon logged for job `id` ("memory estimate 455.2 MiB"), in bytes.
double loggedEstimate(const std::string& log, const std::string& id) {
    size_t line = log.find("[job " + id + "] queued");
    size_t at = line == std::string::npos ? line : log.find("memory estimate ", line);
    if (at == std::string::npos) return 0;
    std::istringstream in(log.substr(at + 16));
    double value = 0;
    std::string unit;
    in >> value >> unit;
    double scale = unit == "KiB"   ? 1024.0
                   : unit == "MiB" ? 1048576.0
                   : unit == "GiB" ? 1073741824.0
                                   : 1.0;
    return value * scale;
}

TEST(ServiceResources, RawPreviewsOverTheirLimitAreRefused) {
    TempDir store;
    Daemon daemon(store.path(), {"--max-raw-preview-mb", "1"});
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    EXPECT_EQ(serverInfo(*stub).limits().max_raw_preview_bytes(), int64_t(1) << 20);
    // 64x48 with 32 type layers, "other" and the combined image: 34 x 3072 x 12 B = 1.2 MiB.
    pb::JobSpec spec = sceneSpec("cornell", 64, 48, 64);
    spec.set_preview_interval_seconds(0.1);
    Submitted job = submit(*stub, spec);
    ASSERT_TRUE(job.status.ok()) << job.status.error_message();
    WatchLog raw = watch(*stub, job.id, true, true);
    EXPECT_EQ(raw.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_NE(raw.status.error_message().find("--max-raw-preview-mb"), std::string::npos)
        << raw.status.error_message();
    WatchLog png = watch(*stub, job.id, true, false);
    EXPECT_TRUE(png.status.ok()) << png.status.error_message();
    EXPECT_EQ(png.last()->state(), pb::JOB_STATE_DONE);
    // Fewer layers: under the limit, raw previews come.
    spec.set_max_type_layers(4);
    Submitted small = submit(*stub, spec);
    ASSERT_TRUE(small.status.ok());
    WatchLog fits = watch(*stub, small.id, true, true);
    EXPECT_TRUE(fits.status.ok()) << fits.status.error_message();
    ASSERT_FALSE(fits.frames().empty());
    EXPECT_FALSE(fits.frames().back()->layers(0).raw_rgb_f32().empty());
}

TEST(ServiceResources, ARawPreviewWatcherKeepsTheJobWithinItsEstimate) {
    // Issue #25 4: cornell-glass, pt, 192x192, 4 spp, 256 layers, previews every 0.05 s and a
    // raw watcher took the daemon +711 MiB over an estimate of 455. The estimate now counts
    // the frames a watcher holds and the raw frames' copies; the daemon's peak (VmHWM) less its
    // resident size before the job must stay under it.
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::JobSpec spec = sceneSpec("cornell-glass", 192, 192, 4);
    spec.set_max_type_layers(256);
    spec.set_preview_interval_seconds(0.05);
    const uint64_t before = procStatusKiB(daemon.pid(), "VmRSS") * 1024;
    Submitted job = submit(*stub, spec);
    ASSERT_TRUE(job.status.ok()) << job.status.error_message();
    // Read every event and keep none (a frame is ~110 MiB of raw pixels).
    auto ctx = context(120s);
    auto reader = stub->WatchJob(ctx.get(), watchRequest(job.id, true, true));
    pb::JobEvent event;
    int frames = 0;
    pb::JobState last = pb::JOB_STATE_UNSPECIFIED;
    while (reader->Read(&event)) {
        if (event.has_preview()) ++frames;
        if (event.has_state()) last = event.state().state();
    }
    ASSERT_TRUE(reader->Finish().ok());
    EXPECT_EQ(last, pb::JOB_STATE_DONE);
    EXPECT_GT(frames, 1);
    const uint64_t peak = procStatusKiB(daemon.pid(), "VmHWM") * 1024;
    const double estimate = loggedEstimate(daemon.log(), job.id);
    ASSERT_GT(estimate, 0) << daemon.log();
    std::printf("raw watcher: daemon peak +%.1f MiB over %d frames, estimate %.1f MiB\n",
                double(peak - before) / 1048576.0, frames, estimate / 1048576.0);
    EXPECT_LE(double(peak - before), estimate)
        << "peak " << (peak - before) / 1048576.0 << " MiB over " << frames << " frames";
}

TEST(ServiceResources, RunningJobsCountAgainstTheTotal) {
    TempDir store;
    // Each job below is estimated at ~154 MiB (1000 type layers on 48x36 pixels, with their
    // preview frames and raw copies): one fits in the total of 250 MiB, two do not, so the
    // second waits although two may run at once.
    Daemon daemon(store.path(),
                  {"--max-jobs", "2", "--max-job-memory", "200", "--max-total-memory", "250"});
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    auto spec = [] {
        pb::JobSpec s = sceneSpec("cornell", 48, 36, 1);
        s.set_max_type_layers(1000);
        s.mutable_budget()->set_kind(pb::BUDGET_KIND_SECONDS);
        s.mutable_budget()->set_amount(60);
        return s;
    };
    Submitted first = submit(*stub, spec());
    ASSERT_TRUE(first.status.ok()) << first.status.error_message();
    ASSERT_TRUE(waitForState(*stub, first.id, pb::JOB_STATE_RENDERING, 30s));
    Submitted second = submit(*stub, spec());
    ASSERT_TRUE(second.status.ok()) << second.status.error_message();
    // A bounded look: the second stays queued while the first renders.
    EXPECT_FALSE(waitForState(*stub, second.id, pb::JOB_STATE_LOADING, 2s));
    pb::GetJobRequest get;
    get.set_job_id(second.id);
    pb::Job job;
    auto ctx = context(10s);
    ASSERT_TRUE(stub->GetJob(ctx.get(), get, &job).ok());
    EXPECT_EQ(job.state(), pb::JOB_STATE_QUEUED);

    pb::CancelJobRequest cancel;
    cancel.set_job_id(first.id);
    auto cctx = context(10s);
    ASSERT_TRUE(stub->CancelJob(cctx.get(), cancel, &job).ok());
    EXPECT_TRUE(waitForState(*stub, second.id, pb::JOB_STATE_RENDERING, 30s))
        << "the second job starts once the first has freed its memory";
    cancel.set_job_id(second.id);
    auto c2 = context(10s);
    EXPECT_TRUE(stub->CancelJob(c2.get(), cancel, &job).ok());
}

/// A watch stream that has received its first event and then reads nothing more.
struct StalledWatcher {
    std::unique_ptr<grpc::ClientContext> ctx = context(60s);
    std::unique_ptr<grpc::ClientReader<pb::JobEvent>> reader;
    bool firstEvent = false;
    StalledWatcher(pb::Partita::Stub& stub, const std::string& id) {
        reader = stub.WatchJob(ctx.get(), watchRequest(id, true, true));
        pb::JobEvent event;
        firstEvent = reader->Read(&event) && event.has_state();
    }
    ~StalledWatcher() {
        ctx->TryCancel();
        reader->Finish();
    }
};

TEST(ServiceResources, WatcherLimitHoldsForFinishedJobsToo) {
    TempDir store;
    Daemon daemon(store.path(), {"--max-watchers", "2"});
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    // Raw final frames of 34 layers (~8 MB) do not fit gRPC's flow-control window: a watcher
    // that stops reading keeps its stream open.
    Submitted job = submit(*stub, sceneSpec("cornell-glass", 160, 120, 4));
    ASSERT_TRUE(job.status.ok()) << job.status.error_message();
    ASSERT_EQ(waitForEnd(*stub, job.id, 60s).state(), pb::JOB_STATE_DONE);

    auto a = std::make_unique<StalledWatcher>(*stub, job.id);
    auto b = std::make_unique<StalledWatcher>(*stub, job.id);
    ASSERT_TRUE(a->firstEvent && b->firstEvent);
    WatchLog third = watch(*stub, job.id);
    EXPECT_EQ(third.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED)
        << third.status.error_message();
    EXPECT_NE(third.status.error_message().find("--max-watchers"), std::string::npos);

    // Once a stream ends, its place is free again (the server notices within a bounded wait).
    a.reset();
    bool accepted = false;
    for (int i = 0; i < 100 && !accepted; ++i) {
        accepted = watch(*stub, job.id).status.ok();
        if (!accepted) std::this_thread::sleep_for(100ms);
    }
    EXPECT_TRUE(accepted);
}

TEST(ServiceResources, WatchStreamsOfAllJobsTogetherAreBounded) {
    TempDir store;
    Daemon daemon(store.path(), {"--max-watch-streams", "2"});
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    Submitted a = submit(*stub, sceneSpec("cornell-glass", 160, 120, 4));
    Submitted b = submit(*stub, sceneSpec("cornell-glass", 160, 120, 4, 2));
    ASSERT_TRUE(a.status.ok() && b.status.ok());
    ASSERT_EQ(waitForEnd(*stub, a.id, 60s).state(), pb::JOB_STATE_DONE);
    ASSERT_EQ(waitForEnd(*stub, b.id, 60s).state(), pb::JOB_STATE_DONE);
    StalledWatcher first(*stub, a.id), second(*stub, b.id);
    ASSERT_TRUE(first.firstEvent && second.firstEvent);
    WatchLog third = watch(*stub, a.id);
    EXPECT_EQ(third.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_NE(third.status.error_message().find("--max-watch-streams"), std::string::npos)
        << third.status.error_message();
}

TEST(ServiceResources, StoreSizeLimitRefusesNewUploads) {
    TempDir store;
    Daemon daemon(store.path(), {"--max-store-mb", "1"});
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    EXPECT_EQ(serverInfo(*stub).limits().max_store_bytes(), int64_t(1) << 20);

    pb::JobSpec big;
    big.mutable_scene()->set_glb(makeGridGlb(300));  // a few MB
    ASSERT_GT(big.scene().glb().size(), size_t(1) << 20);
    big.set_width(16);
    big.set_height(16);
    Submitted refused = submit(*stub, big);
    EXPECT_EQ(refused.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_NE(refused.status.error_message().find("--max-store-mb"), std::string::npos)
        << refused.status.error_message();

    pb::JobSpec small;
    small.mutable_scene()->set_glb(makeGridGlb(10));
    small.set_width(16);
    small.set_height(16);
    Submitted ok = submit(*stub, small);
    EXPECT_TRUE(ok.status.ok()) << ok.status.error_message();
    // Named scenes take no store space before they render: still accepted.
    EXPECT_TRUE(submit(*stub, sceneSpec("cornell", 16, 16, 1)).status.ok());
}

TEST(ServiceResources, TheDefaultStoreLimitIsNoMoreThanTheStoreCanGrowTo) {
    // Half the disk's capacity can be more than is free (issue #25 7): the default is at most
    // the free space plus what the store holds (1 GiB of slack for other writers meanwhile).
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    pb::ServerInfo info;
    auto ctx = context(10s);
    ASSERT_TRUE(stub->GetServerInfo(ctx.get(), pb::ServerInfoRequest{}, &info).ok());
    fs::space_info space = fs::space(store.path());
    uint64_t limit = uint64_t(info.limits().max_store_bytes());
    EXPECT_GT(limit, 0u);
    EXPECT_LE(limit, uint64_t(space.capacity) / 2);
    EXPECT_LE(limit, uint64_t(space.available) + (uint64_t(1) << 30));
}

}  // namespace
}  // namespace partita::test
