// The job system in one process, without gRPC: client threads submit, watch, cancel, list and
// delete jobs while the runners render them on the shared pool. In the plain build this checks
// that every job ends as its client asked and that every watch sees its job's states in order and
// ends exactly once; under ThreadSanitizer (make test-tsan) it is the race check of the job
// manager, the jobs' records and their watchers (the gRPC service's own threads cannot run under
// TSan here: Debian's gRPC is not instrumented, see the Makefile).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "job.h"
#include "job_api.h"
#include "job_manager.h"
#include "job_store.h"
#include "scene_source.h"
#include "service_limits.h"
#include "temp_dir.h"

namespace partita::server {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

/// Records what a watch receives; called with the job's lock held, as the service's are.
class RecordingWatcher : public JobWatcher {
  public:
    void onState(const pb::Job& job) override {
        std::lock_guard lock(mutex_);
        states_.push_back(job.state());
    }
    void onProgress(const pb::Progress&) override { progress_.fetch_add(1); }
    void onFrame(std::shared_ptr<const PreviewFrameData> frame) override {
        if (frame) frames_.fetch_add(1);
    }
    void onClose(const grpc::Status& status) override {
        std::lock_guard lock(mutex_);
        closes_.push_back(status.error_code());
    }

    std::vector<pb::JobState> states() const {
        std::lock_guard lock(mutex_);
        return states_;
    }
    std::vector<grpc::StatusCode> closes() const {
        std::lock_guard lock(mutex_);
        return closes_;
    }

  private:
    mutable std::mutex mutex_;
    std::vector<pb::JobState> states_;
    std::vector<grpc::StatusCode> closes_;
    std::atomic<int> progress_{0}, frames_{0};
};

pb::JobSpec smallJob(uint64_t seed, double spp) {
    pb::JobSpec spec;
    spec.mutable_scene()->set_scene_name("cornell");
    spec.set_width(24);
    spec.set_height(16);
    spec.set_algorithm("pt");
    spec.mutable_budget()->set_kind(pb::BUDGET_KIND_SAMPLES_PER_PIXEL);
    spec.mutable_budget()->set_amount(spp);
    spec.set_seed(seed);
    return spec;
}

pb::JobState stateOf(const JobApi& api, const std::string& id) {
    pb::Job job;
    EXPECT_TRUE(api.get(id, job).ok()) << id;
    return job.state();
}

/// Waits (at most a minute) until the job has ended.
pb::JobState waitForEnd(const JobApi& api, const std::string& id) {
    const auto deadline = std::chrono::steady_clock::now() + 60s;
    pb::JobState state = stateOf(api, id);
    while (!isTerminal(state) && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(5ms);
        state = stateOf(api, id);
    }
    return state;
}

struct ClientJob {
    std::string id;
    bool cancelled = false;
    std::shared_ptr<RecordingWatcher> watcher = std::make_shared<RecordingWatcher>();
};

/// One client: submits `jobs` jobs, watches each (with previews), cancels every third right
/// away, lists, waits for the others to end and deletes them all. Failures are gtest failures.
std::vector<ClientJob> runClient(JobApi& api, int client, int jobs) {
    std::vector<ClientJob> mine;
    for (int j = 0; j < jobs; ++j) {
        ClientJob job;
        pb::Job submitted;
        grpc::Status s = api.submit(smallJob(uint64_t(100 * client + j), 2 + j % 3), submitted);
        EXPECT_TRUE(s.ok()) << s.error_message();
        if (!s.ok()) continue;
        job.id = submitted.id();
        std::shared_ptr<Job> found = api.find(job.id);
        EXPECT_TRUE(found);
        if (found) {
            EXPECT_TRUE(found->addWatcher(job.watcher, true, 64).ok());
        }
        if (j % 3 == 1) {
            pb::Job cancelled;
            EXPECT_TRUE(api.cancel(job.id, cancelled).ok());
            job.cancelled = true;
            // Deleted while it may still be stopping: its record goes when the render ends.
            EXPECT_TRUE(api.remove(job.id).ok());
        }
        mine.push_back(std::move(job));
    }
    pb::ListJobsRequest request;
    pb::ListJobsResponse listed;
    EXPECT_TRUE(api.list(request, listed).ok());
    for (ClientJob& job : mine) {
        if (job.cancelled) continue;
        EXPECT_EQ(waitForEnd(api, job.id), pb::JOB_STATE_DONE) << job.id;
        EXPECT_TRUE(api.remove(job.id).ok()) << job.id;
    }
    return mine;
}

TEST(JobManagerThreads, ClientsSubmitWatchCancelAndDeleteWhileRunnersRender) {
    test::TempDir dir;
    JobStore store(dir.path() / "store");
    SceneSource scenes(PARTITA_SCENES_DIR);
    ServiceLimits limits;
    JobManager manager(store, scenes, limits, /*threads=*/2, /*maxJobs=*/2);
    manager.start();
    JobApi api(manager, scenes, limits);

    constexpr int kClients = 4, kJobsEach = 4;
    std::vector<std::vector<ClientJob>> results(kClients);
    std::vector<std::thread> clients;
    for (int c = 0; c < kClients; ++c)
        clients.emplace_back([&, c] { results[size_t(c)] = runClient(api, c, kJobsEach); });
    for (auto& t : clients) t.join();

    // Every job is gone, from the listing and (once its render stopped) from the store.
    pb::ListJobsResponse listed;
    EXPECT_TRUE(api.list(pb::ListJobsRequest(), listed).ok());
    EXPECT_EQ(listed.jobs_size(), 0);
    manager.shutdown();
    EXPECT_TRUE(store.loadAll().empty());

    for (const auto& mine : results) {
        ASSERT_EQ(mine.size(), size_t(kJobsEach));
        for (const ClientJob& job : mine) {
            const std::vector<pb::JobState> states = job.watcher->states();
            ASSERT_FALSE(states.empty()) << job.id;
            for (size_t i = 1; i < states.size(); ++i)
                EXPECT_TRUE(!isTerminal(states[i - 1])) << job.id << ": a state after the end";
            // A watch ends exactly once: by its job's terminal state, or (deleted while it was
            // still stopping) by one close.
            const std::vector<grpc::StatusCode> closes = job.watcher->closes();
            if (isTerminal(states.back()))
                EXPECT_TRUE(closes.empty()) << job.id << ": closed after its end";
            else
                EXPECT_EQ(closes, std::vector<grpc::StatusCode>{grpc::StatusCode::NOT_FOUND})
                    << job.id << ": one close, by the delete";
            if (!job.cancelled) {
                EXPECT_EQ(states.back(), pb::JOB_STATE_DONE) << job.id;
            }
        }
    }
}

}  // namespace
}  // namespace partita::server
