#include "slurm_shards.h"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <chrono>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "job_store.h"
#include "progress_reporter.h"
#include "subprocess.h"

namespace partita::server {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPlanFile = "job.plan";
constexpr const char* kStateFile = "state.json";
/// A shard that has neither a file nor a live task in this many polls in a row failed (one
/// poll could fall between a task's end and squeue catching up).
constexpr int kMissingPolls = 2;
/// squeue failing this many polls in a row fails the job.
constexpr int kSqueueFailures = 30;

/// What partitad remembers of a job's array across restarts.
struct ArrayState {
    std::string arrayId;                      // of `sbatch --array=0..N-1`
    std::map<uint32_t, std::string> retries;  // shard -> job id of its second submission
};

void saveState(const fs::path& dir, const ArrayState& s) {
    nlohmann::json j;
    j["array"] = s.arrayId;
    nlohmann::json retries = nlohmann::json::object();
    for (const auto& [shard, id] : s.retries) retries[std::to_string(shard)] = id;
    j["retries"] = retries;
    JobStore::writeFileAtomic(dir / kStateFile, j.dump(2) + "\n");
}

bool loadState(const fs::path& dir, ArrayState& s) {
    std::error_code ec;
    if (!fs::exists(dir / kStateFile, ec) || !fs::exists(dir / kPlanFile, ec)) return false;
    try {
        std::vector<uint8_t> bytes = readFileBytes((dir / kStateFile).string());
        nlohmann::json j = nlohmann::json::parse(bytes.begin(), bytes.end());
        s.arrayId = j.at("array").get<std::string>();
        for (const auto& [shard, id] : j.at("retries").items())
            s.retries[uint32_t(std::stoul(shard))] = id.get<std::string>();
        return !s.arrayId.empty();
    } catch (const std::exception&) {
        return false;  // a damaged state: plan and submit again
    }
}

fs::path shardFile(const fs::path& dir, uint32_t shard) {
    return dir / ("shard-" + std::to_string(shard) + ".bin");
}

/// A single-quoted shell word.
std::string shellQuote(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

class Slurm {
  public:
    Slurm(const SlurmJob& job, std::string worker) : job_(job), worker_(std::move(worker)) {}

    /// Submits shards [first, last] as one array; its job id.
    std::string submit(uint32_t first, uint32_t last) const {
        const fs::path plan = job_.dir / kPlanFile;
        const int cpus = std::max(1, job_.options.cpusPerTask);
        // The task's shell fills in its index; the paths are quoted for it.
        std::string script =
            "exec " + shellQuote(worker_) + " render --plan " + shellQuote(plan.string()) +
            " --quiet --threads " + std::to_string(cpus) + " --out " +
            shellQuote((job_.dir / "shard-").string()) + "\"$SLURM_ARRAY_TASK_ID\".bin";
        std::vector<std::string> argv = {
            "sbatch",
            "--parsable",
            "--array=" + std::to_string(first) + "-" + std::to_string(last),
            "--job-name=" + job_.name,
            "--cpus-per-task=" + std::to_string(cpus),
            "--output=" + (job_.dir / "shard-%a.log").string(),
            "--chdir=" + job_.dir.string()};
        if (!job_.options.partition.empty())
            argv.push_back("--partition=" + job_.options.partition);
        argv.push_back("--wrap=" + script);
        ProcessResult r = runProcess(argv);
        std::string id = r.out.substr(0, r.out.find_first_of(";\n"));
        if (!r.ok() || id.empty())
            throw std::runtime_error("cannot submit the shards: " + r.describe("sbatch"));
        return id;
    }

    /// The shard indices of this job's tasks that Slurm still holds (pending, running,
    /// completing, ...); false when squeue fails.
    bool liveShards(std::set<uint32_t>& live) const {
        ProcessResult r = runProcess({"squeue", "-h", "-r", "--name=" + job_.name, "-o", "%i %T"});
        if (!r.ok()) return false;
        std::istringstream lines(r.out);
        std::string id, state;
        while (lines >> id >> state) {
            size_t underscore = id.find('_');
            if (underscore == std::string::npos) continue;
            try {
                live.insert(uint32_t(std::stoul(id.substr(underscore + 1))));
            } catch (const std::exception&) {
            }
        }
        return true;
    }

    void cancel(const ArrayState& state) const {
        std::vector<std::string> argv = {"scancel", state.arrayId};
        for (const auto& [shard, id] : state.retries) argv.push_back(id);
        ProcessResult r = runProcess(argv);
        if (!r.ok()) spdlog::warn("{} {}", job_.tag, r.describe("scancel"));
    }

  private:
    const SlurmJob& job_;
    std::string worker_;
};

/// Plans and submits, or finds the plan and the array of an earlier run of this job.
ShardPlan planOrResume(const SlurmJob& job, const ShardEnvironment& env, const Slurm& slurm,
                       ArrayState& state) {
    if (loadState(job.dir, state)) {
        ShardPlan plan = deserializeShardPlan(readFileBytes((job.dir / kPlanFile).string()));
        spdlog::info("{} found its Slurm array {} again ({} shards)", job.tag, state.arrayId,
                     plan.shards);
        return plan;
    }
    const uint64_t digest = fileChecksum(readFileBytes(job.scenePath));
    ShardPlan plan =
        planShardedRender(env, job.algorithm, job.settings,
                          uint32_t(std::max(1, job.options.shards)), job.scenePath, digest);
    writeFileAtomic(job.dir / kPlanFile, serializeShardPlan(plan));
    state = ArrayState{};
    state.arrayId = slurm.submit(0, plan.shards - 1);
    saveState(job.dir, state);
    spdlog::info("{} submitted {} shards as Slurm array {}", job.tag, plan.shards, state.arrayId);
    return plan;
}

/// Follows the array until every shard is merged.
class Follower {
  public:
    Follower(const SlurmJob& job, const ShardEnvironment& env, const Slurm& slurm,
             const ShardPlan& plan, ArrayState& state)
        : job_(job),
          env_(env),
          slurm_(slurm),
          plan_(plan),
          state_(state),
          merger_(plan),
          progress_(env.observer, "render", "shards", double(plan.shards)) {}

    const ShardMerger& run() {
        while (!merger_.complete()) {
            checkCancel();
            std::set<uint32_t> live;
            // squeue first, then the files: a task that is gone has renamed its file into
            // place before it ended.
            bool known = slurm_.liveShards(live);
            failedQueries_ = known ? 0 : failedQueries_ + 1;
            if (failedQueries_ >= kSqueueFailures)
                throw std::runtime_error("squeue has failed " + std::to_string(failedQueries_) +
                                         " times in a row");
            if (mergeNewShards() && !merger_.complete()) publishPreview();
            if (known) retryLostShards(live);
            if (!merger_.complete())
                std::this_thread::sleep_for(std::chrono::milliseconds(
                    int64_t(std::max(0.05, job_.options.pollSeconds) * 1000)));
        }
        progress_.flush();
        return merger_;
    }

  private:
    void checkCancel() const {
        if (!env_.cancel.load()) return;
        if (!job_.shuttingDown || !job_.shuttingDown()) {
            slurm_.cancel(state_);
            spdlog::info("{} cancelled Slurm array {}", job_.tag, state_.arrayId);
        }
        throw RenderCancelled{};
    }

    /// Merges every shard file that has appeared; whether any was new.
    bool mergeNewShards() {
        bool merged = false;
        for (uint32_t i : merger_.missing()) {
            const fs::path file = shardFile(job_.dir, i);
            std::error_code ec;
            if (!fs::exists(file, ec)) continue;
            try {
                if (merger_.add(deserializeShardResult(readFileBytes(file.string())))) {
                    progress_.advance(1);
                    merged = true;
                }
            } catch (const std::exception& e) {
                // A damaged or foreign file: gone, so that the shard counts as lost.
                spdlog::warn("{} shard {}: {}; discarded", job_.tag, i, e.what());
                fs::remove(file, ec);
            }
        }
        return merged;
    }

    /// A shard with neither a file nor a live task lost its task: submitted again once.
    void retryLostShards(const std::set<uint32_t>& live) {
        for (uint32_t i : merger_.missing()) {
            std::error_code ec;
            if (live.count(i) || fs::exists(shardFile(job_.dir, i), ec)) {
                missing_[i] = 0;
                continue;
            }
            if (++missing_[i] < kMissingPolls) continue;
            missing_[i] = 0;
            if (state_.retries.count(i))
                throw std::runtime_error(
                    "shard " + std::to_string(i) + " failed twice; its log: " +
                    (job_.dir / ("shard-" + std::to_string(i) + ".log")).string());
            state_.retries[i] = slurm_.submit(i, i);
            saveState(job_.dir, state_);
            spdlog::warn("{} shard {} ended without its result; submitted again as job {}",
                         job_.tag, i, state_.retries[i]);
        }
    }

    void publishPreview() {
        RenderResult preview = resolveShardedRender(env_, plan_, merger_.work());
        preview.stats.values["shards_merged"] = double(merger_.mergedCount());
        env_.observer.onPreview(std::move(preview.image), preview.stats);
    }

    const SlurmJob& job_;
    const ShardEnvironment& env_;
    const Slurm& slurm_;
    const ShardPlan& plan_;
    ArrayState& state_;
    ShardMerger merger_;
    ProgressReporter progress_;
    std::map<uint32_t, int> missing_;  // polls in a row without file or task
    int failedQueries_ = 0;
};

}  // namespace

RenderResult renderOnSlurm(const SlurmJob& job, const ShardEnvironment& env) {
    const std::string worker = findShardWorker(job.options.worker);
    if (worker.empty())
        throw std::runtime_error(
            "executor slurm: no partita-local to run the shards (give --slurm-worker)");
    fs::create_directories(job.dir);
    Slurm slurm(job, worker);
    ArrayState state;
    const ShardPlan plan = planOrResume(job, env, slurm, state);
    Follower follower(job, env, slurm, plan, state);
    const ShardMerger* mergedPointer = nullptr;
    try {
        mergedPointer = &follower.run();
    } catch (const RenderCancelled&) {
        throw;  // scancel'ed already, or left running for the restart
    } catch (const std::exception&) {
        slurm.cancel(state);  // the job fails: its other tasks have nothing left to do
        throw;
    }
    const ShardMerger& merged = *mergedPointer;
    RenderResult result = resolveShardedRender(env, plan, merged.work());
    result.stats.values["shards"] = double(plan.shards);
    result.stats.values["shard_retries"] = double(state.retries.size());
    result.stats.labels["slurm_array"] = state.arrayId;
    return result;
}

void removeSlurmFiles(const fs::path& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (entry.path().extension() == ".log") continue;
        if (name.rfind("shard-", 0) == 0 || name == kPlanFile || name == kStateFile)
            fs::remove(entry.path(), ec);
    }
}

std::string checkSlurmExecutor(const ClusterOptions& options) {
    if (!options.slurm()) return {};
    for (const char* tool : {"sbatch", "squeue", "scancel"})
        if (!runProcess({tool, "--version"}, 20).ok())
            return std::string("--executor slurm needs '") + tool +
                   "' on the PATH (Debian: slurm-client)";
    if (findShardWorker(options.worker).empty())
        return "--executor slurm: no partita-local found beside partitad; give --slurm-worker";
    if (!options.worker.empty() && access(options.worker.c_str(), X_OK) != 0)
        return "--slurm-worker '" + options.worker + "' is not an executable file";
    return {};
}

std::string findShardWorker(const std::string& configured) {
    if (!configured.empty()) return configured;
    std::error_code ec;
    fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return {};
    for (const fs::path& candidate :
         {self.parent_path() / "partita-local",
          self.parent_path().parent_path() / "tools" / "local" / "partita-local"})
        if (access(candidate.c_str(), X_OK) == 0) return candidate.string();
    return {};
}

}  // namespace partita::server
