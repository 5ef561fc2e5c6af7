// Many clients at once: each submits a small job on its own connection, watches it to DONE and
// fetches the result, while the daemon runs several jobs on one shared thread pool.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "service_client.h"

namespace partita::test {
namespace {

using namespace std::chrono_literals;

TEST(ServiceConcurrency, TwentyFourClientsSubmitWatchAndFetch) {
    TempDir store;
    Daemon daemon(store.path(), {"--max-jobs", "4"});
    ASSERT_TRUE(daemon.running());
    constexpr int kClients = 24;
    std::atomic<int> done{0}, withFrames{0};
    std::vector<std::string> failures(kClients);
    std::vector<std::thread> clients;
    auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < kClients; ++i) {
        clients.emplace_back([&, i] {
            auto stub = daemon.stub();  // a connection of its own
            pb::JobSpec spec =
                sceneSpec(i % 2 ? "cornell" : "cornell-glass", 32, 24, 2, uint64_t(i + 1));
            spec.set_priority(i % 3);
            spec.set_label("client-" + std::to_string(i));
            Submitted job = submit(*stub, spec);
            if (!job.status.ok()) {
                failures[i] = "submit: " + job.status.error_message();
                return;
            }
            WatchLog log = watch(*stub, job.id, /*previews=*/true);
            if (!log.status.ok() || !log.last() || log.last()->state() != pb::JOB_STATE_DONE) {
                failures[i] = "watch: " + log.status.error_message() +
                              (log.last() ? " " + log.last()->error() : "");
                return;
            }
            if (!log.frames().empty() && log.frames().back()->final()) ++withFrames;
            Fetched exr = fetch(*stub, job.id, pb::RESULT_KIND_EXR);
            if (!exr.status.ok() || exr.bytes.size() < 100) {
                failures[i] = "fetch: " + exr.status.error_message();
                return;
            }
            ++done;
        });
    }
    for (auto& t : clients) t.join();
    for (int i = 0; i < kClients; ++i) EXPECT_EQ(failures[i], "") << "client " << i;
    EXPECT_EQ(done.load(), kClients);
    EXPECT_EQ(withFrames.load(), kClients) << "every watcher got the final frame";
    std::printf("%d clients done in %.2f s\n", kClients,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());

    auto stub = daemon.stub();
    pb::ListJobsRequest list;
    list.add_states(pb::JOB_STATE_DONE);
    pb::ListJobsResponse jobs;
    auto ctx = context();
    ASSERT_TRUE(stub->ListJobs(ctx.get(), list, &jobs).ok());
    EXPECT_EQ(jobs.jobs_size(), kClients);
    EXPECT_EQ(daemon.stop(SIGTERM), 0);
}

}  // namespace
}  // namespace partita::test
