// partitad --executor slurm on a real one-node Slurm cluster (munged, slurmctld and slurmd
// started for these tests by tests/slurm/slurm_cluster.sh; the tests skip, saying why, where
// that cannot start, e.g. without root): a job is planned by partitad, its shards run as an
// array of partita-local tasks, and the result is bit-identical to the in-process render; a
// shard killed with scancel is run again; a cancelled job scancels its array; a partitad
// restart in the middle finds the running array again.
#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>
#include <thread>

#include "in_process.h"
#include "service_client.h"

namespace partita::test {
namespace {

using namespace std::chrono_literals;

const fs::path kScenes = PARTITA_SCENES_DIR;

/// Runs a shell command line; its exit status and stdout.
std::pair<int, std::string> shell(const std::string& command) {
    std::string out;
    FILE* pipe = popen((command + " 2>&1").c_str(), "r");
    if (!pipe) return {-1, out};
    char buffer[4096];
    while (size_t n = fread(buffer, 1, sizeof buffer, pipe)) out.append(buffer, n);
    int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

class ServiceSlurm : public testing::Test {
  protected:
    static void SetUpTestSuite() {
        cluster_ = new TempDir;
        auto [code, out] = shell("SLURM_CLUSTER_CPUS=4 " + std::string(PARTITA_SLURM_CLUSTER) +
                                 " start " + cluster_->path().string());
        const std::string prefix = "export SLURM_CONF=";
        if (code != 0 || out.rfind(prefix, 0) != 0) {
            skipReason_ = out.empty() ? "slurm_cluster.sh failed" : out;
            return;
        }
        std::string conf = out.substr(prefix.size());
        conf = conf.substr(0, conf.find('\n'));
        setenv("SLURM_CONF", conf.c_str(), 1);
        started_ = true;
    }
    static void TearDownTestSuite() {
        if (started_)
            shell(std::string(PARTITA_SLURM_CLUSTER) + " stop " + cluster_->path().string());
        unsetenv("SLURM_CONF");
        delete cluster_;
        cluster_ = nullptr;
        started_ = false;
    }
    void SetUp() override {
        if (!started_) GTEST_SKIP() << "no Slurm cluster here: " << skipReason_;
    }

    static std::vector<std::string> slurmFlags(int shards) {
        return {"--executor",           "slurm",
                "--slurm-shards",       std::to_string(shards),
                "--slurm-worker",       PARTITA_LOCAL_PATH,
                "--slurm-poll-seconds", "0.1"};
    }

    /// The job ids Slurm still holds for partitad job `id`, one "ARRAY_INDEX STATE" a line.
    static std::string tasksOf(const std::string& id) {
        return shell("squeue -h -r --name=partita-" + id + " -o '%i %T'").second;
    }

    static void expectLikeInProcess(pb::Partita::Stub& stub, const std::string& id,
                                    const std::string& scene, int w, int h, double budget,
                                    uint64_t seed, const std::string& algorithm) {
        Fetched exr = fetch(stub, id, pb::RESULT_KIND_EXR);
        ASSERT_TRUE(exr.status.ok()) << exr.status.error_message();
        LayeredImage local =
            renderInProcess(kScenes / scene / (scene + ".gltf"), w, h, budget, seed, algorithm);
        EXPECT_EQ(compareImages(readExrBytes(exr.bytes), local), "");
    }

    static inline TempDir* cluster_ = nullptr;
    static inline bool started_ = false;
    static inline std::string skipReason_;
};

pb::JobSpec mltSpec(const std::string& scene, int w, int h, double mpp, uint64_t seed) {
    pb::JobSpec spec = sceneSpec(scene, w, h, mpp, seed);
    spec.set_algorithm("mlt");
    spec.mutable_budget()->set_kind(pb::BUDGET_KIND_MUTATIONS_PER_PIXEL);
    return spec;
}

TEST_F(ServiceSlurm, ShardedJobsAreBitIdenticalToTheInProcessRender) {
    TempDir store;
    Daemon daemon(store.path(), slurmFlags(3));
    ASSERT_TRUE(daemon.running()) << daemon.log();
    auto stub = daemon.stub();
    Submitted pt = submit(*stub, sceneSpec("cornell", 48, 36, 12, 3));
    Submitted mlt = submit(*stub, mltSpec("cornell-glass", 40, 30, 4, 5));
    ASSERT_TRUE(pt.status.ok() && mlt.status.ok());
    for (const std::string& id : {pt.id, mlt.id}) {
        pb::Job end = waitForEnd(*stub, id, 120s);
        ASSERT_EQ(end.state(), pb::JOB_STATE_DONE) << end.error() << "\n" << daemon.log();
        EXPECT_EQ(end.stats().at("shards"), 3.0);
        EXPECT_EQ(end.stats().at("shard_retries"), 0.0);
    }
    expectLikeInProcess(*stub, pt.id, "cornell", 48, 36, 12, 3, "pt");
    expectLikeInProcess(*stub, mlt.id, "cornell-glass", 40, 30, 4, 5, "mlt");
    EXPECT_NE(daemon.log().find("submitted 3 shards as Slurm array"), std::string::npos)
        << daemon.log();
}

TEST_F(ServiceSlurm, ARelativeStoreWorks) {
    // Slurm resolves --output against --chdir, so a relative store failed every sharded job
    // with a log that did not exist (issue #25 6): partitad makes the store absolute.
    TempDir store;
    fs::path relative = fs::relative(store.path());
    ASSERT_TRUE(relative.is_relative()) << relative;
    Daemon daemon(relative, slurmFlags(2));
    ASSERT_TRUE(daemon.running()) << daemon.log();
    auto stub = daemon.stub();
    Submitted pt = submit(*stub, sceneSpec("cornell", 24, 18, 4, 3));
    ASSERT_TRUE(pt.status.ok()) << pt.status.error_message();
    pb::Job end = waitForEnd(*stub, pt.id, 120s);
    ASSERT_EQ(end.state(), pb::JOB_STATE_DONE) << end.error() << "\n" << daemon.log();
    EXPECT_EQ(end.stats().at("shards"), 2.0);
    expectLikeInProcess(*stub, pt.id, "cornell", 24, 18, 4, 3, "pt");
}

TEST_F(ServiceSlurm, AKilledShardIsRunAgainAndTheResultStaysTheSame) {
    TempDir store;
    Daemon daemon(store.path(), slurmFlags(3));
    ASSERT_TRUE(daemon.running()) << daemon.log();
    auto stub = daemon.stub();
    Submitted job = submit(*stub, sceneSpec("cornell", 64, 48, 96, 4));
    ASSERT_TRUE(job.status.ok());
    ASSERT_TRUE(waitForState(*stub, job.id, pb::JOB_STATE_RENDERING, 60s));
    // Shard 2, pending or running: killed before it can write its result.
    std::string tasks;
    for (int i = 0; i < 50 && tasks.find("_2 ") == std::string::npos; ++i) {
        tasks = tasksOf(job.id);
        if (tasks.find("_2 ") == std::string::npos) std::this_thread::sleep_for(20ms);
    }
    const size_t at = tasks.find("_2 ");
    ASSERT_NE(at, std::string::npos) << "shard 2 was never seen in squeue: " << tasks;
    const size_t begin = tasks.rfind('\n', at) == std::string::npos ? 0 : tasks.rfind('\n', at) + 1;
    const std::string task = tasks.substr(begin, at + 2 - begin);
    EXPECT_EQ(shell("scancel " + task).first, 0) << task;
    pb::Job end = waitForEnd(*stub, job.id, 120s);
    ASSERT_EQ(end.state(), pb::JOB_STATE_DONE) << end.error() << "\n" << daemon.log();
    EXPECT_EQ(end.stats().at("shard_retries"), 1.0) << daemon.log();
    EXPECT_NE(daemon.log().find("shard 2 ended without its result; submitted again"),
              std::string::npos)
        << daemon.log();
    expectLikeInProcess(*stub, job.id, "cornell", 64, 48, 96, 4, "pt");
}

TEST_F(ServiceSlurm, CancellingAJobCancelsItsArray) {
    TempDir store;
    Daemon daemon(store.path(), slurmFlags(3));
    ASSERT_TRUE(daemon.running()) << daemon.log();
    auto stub = daemon.stub();
    Submitted job = submit(*stub, sceneSpec("cornell", 128, 96, 4096, 1));  // minutes
    ASSERT_TRUE(job.status.ok());
    ASSERT_TRUE(waitForState(*stub, job.id, pb::JOB_STATE_RENDERING, 60s));
    ASSERT_FALSE(tasksOf(job.id).empty());
    pb::CancelJobRequest request;
    request.set_job_id(job.id);
    pb::Job response;
    auto ctx = context();
    ASSERT_TRUE(stub->CancelJob(ctx.get(), request, &response).ok());
    EXPECT_EQ(waitForEnd(*stub, job.id, 20s).state(), pb::JOB_STATE_CANCELLED);
    std::string left = tasksOf(job.id);
    for (int i = 0; i < 100 && !left.empty(); ++i) {
        std::this_thread::sleep_for(50ms);
        left = tasksOf(job.id);
    }
    EXPECT_EQ(left, "") << "tasks left after the cancel";
}

TEST_F(ServiceSlurm, ARestartedDaemonFindsTheRunningArrayAgain) {
    TempDir store;
    std::string id;
    {
        Daemon first(store.path(), slurmFlags(3));
        ASSERT_TRUE(first.running()) << first.log();
        auto stub = first.stub();
        Submitted job = submit(*stub, sceneSpec("cornell", 64, 48, 128, 6));
        ASSERT_TRUE(job.status.ok());
        id = job.id;
        ASSERT_TRUE(waitForState(*stub, id, pb::JOB_STATE_RENDERING, 60s));
        EXPECT_EQ(first.stop(SIGTERM), 0) << first.log();
    }
    Daemon second(store.path(), slurmFlags(3));
    ASSERT_TRUE(second.running()) << second.log();
    auto stub = second.stub();
    pb::Job end = waitForEnd(*stub, id, 120s);
    ASSERT_EQ(end.state(), pb::JOB_STATE_DONE) << end.error() << "\n" << second.log();
    EXPECT_NE(second.log().find("found its Slurm array"), std::string::npos) << second.log();
    EXPECT_EQ(second.log().find("submitted 3 shards"), std::string::npos) << second.log();
    expectLikeInProcess(*stub, id, "cornell", 64, 48, 128, 6, "pt");
}

TEST_F(ServiceSlurm, WatchersSeeTheShardsMergedSoFar) {
    TempDir store;
    // Two CPUs a task on the cluster's four: the third shard starts when one of the first two
    // has ended, so a preview of the merged shards comes before the final frame.
    std::vector<std::string> flags = slurmFlags(3);
    flags.insert(flags.end(), {"--slurm-cpus-per-task", "2"});
    Daemon daemon(store.path(), flags);
    ASSERT_TRUE(daemon.running()) << daemon.log();
    auto stub = daemon.stub();
    Submitted job = submit(*stub, sceneSpec("cornell", 64, 48, 48, 8));
    ASSERT_TRUE(job.status.ok());
    WatchLog log = watch(*stub, job.id, /*previews=*/true, /*raw=*/true, 120s);
    ASSERT_TRUE(log.status.ok()) << log.status.error_message();
    ASSERT_EQ(log.last()->state(), pb::JOB_STATE_DONE) << daemon.log();
    auto frames = log.frames();
    ASSERT_GE(frames.size(), 2u) << "a preview of merged shards and the final frame";
    EXPECT_FALSE(frames.front()->final());
    EXPECT_TRUE(frames.back()->final());
    double shardsTotal = 0;
    for (const pb::JobEvent& e : log.events)
        if (e.has_progress() && e.progress().unit() == "shards") shardsTotal = e.progress().total();
    EXPECT_EQ(shardsTotal, 3.0) << "progress counts shards";
    expectLikeInProcess(*stub, job.id, "cornell", 64, 48, 48, 8, "pt");
}

TEST(ServiceSlurmOptions, BadExecutorFlagsAreOneLineErrors) {
    TempDir store;
    auto [code, out] = runPartitad({"--store", store.path().string(), "--executor", "cloud"});
    EXPECT_EQ(code, 2);
    EXPECT_NE(out.find("--executor must be local or slurm"), std::string::npos) << out;
    std::tie(code, out) = runPartitad(
        {"--store", store.path().string(), "--executor", "slurm", "--slurm-shards", "0"});
    EXPECT_EQ(code, 2);
    EXPECT_NE(out.find("--slurm-shards"), std::string::npos) << out;
    std::tie(code, out) = runPartitad({"--store", store.path().string(), "--executor", "slurm",
                                       "--slurm-worker", "/nonexistent/partita-local"});
    EXPECT_EQ(code, 2);
    EXPECT_NE(out.find("partitad: error:"), std::string::npos) << out;
}

}  // namespace
}  // namespace partita::test
