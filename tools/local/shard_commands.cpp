#include "shard_commands.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <future>
#include <stdexcept>
#include <thread>
#include <utility>

#include "clock.h"
#include "file_io.h"
#include "frontend/progress_bar.h"
#include "image_io.h"
#include "local_run.h"
#include "renderer.h"
#include "shard/sharded_render.h"
#include "thread_pool.h"

namespace fs = std::filesystem;

namespace partita {

namespace {

/// What a command renders with: the pool, the cancel flag, and a progress bar unless quiet.
class CommandRun {
  public:
    CommandRun(int threads, bool quiet)
        : pool_(threads), bar_(!quiet && ProgressBar::stderrIsTerminal()), observer_(bar_, quiet) {}
    ShardEnvironment environment(const RenderScene& scene) {
        return {scene, pool_, cancel_, observer_};
    }
    /// Ends the bar's line before the command prints its own.
    void finish() { bar_.finish(); }
    int threads() const { return pool_.threadCount(); }

  private:
    ThreadPool pool_;
    std::atomic<bool> cancel_{false};
    ProgressBar bar_;
    BarObserver observer_;
};

/// The scene of a plan, checked against the digest taken when the plan was made.
RenderScene loadPlannedScene(const ShardPlan& plan) {
    if (fileChecksum(readFileBytes(plan.scene)) != plan.sceneDigest)
        throw std::runtime_error("scene '" + plan.scene + "' has changed since the plan was made");
    return loadLocalScene(plan.scene, plan.settings.environment);
}

ShardPlan readPlan(const std::string& path) {
    try {
        return deserializeShardPlan(readFileBytes(path));
    } catch (const std::invalid_argument& e) {
        throw std::runtime_error("'" + path + "': " + e.what());
    }
}

std::optional<uint32_t> parseIndex(const char* text) {
    if (!text || !*text) return std::nullopt;
    char* end = nullptr;
    unsigned long v = std::strtoul(text, &end, 10);
    if (*end != '\0' || v > UINT32_MAX) return std::nullopt;
    return uint32_t(v);
}

}  // namespace

std::optional<uint32_t> shardIndexFromEnvironment() {
    for (const char* name : {"SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"}) {
        const char* value = std::getenv(name);
        if (!value) continue;
        if (auto index = parseIndex(value)) return index;
        throw std::invalid_argument(std::string("$") + name + " is not a shard index: '" + value +
                                    "'");
    }
    return std::nullopt;
}

int runPlanCommand(const PlanCommand& command, RenderOptions& options, bool quiet) {
    if (std::string err = finalizeRenderOptions(options); !err.empty())
        throw std::invalid_argument(err);
    if (command.shards == 0) throw std::invalid_argument("--shards must be at least 1");
    requireOutputFolder(command.out);
    const std::string scenePath = fs::absolute(command.scene).lexically_normal().string();
    const uint64_t digest = fileChecksum(readFileBytes(scenePath));
    RenderScene scene = loadLocalScene(scenePath, options.settings.environment);
    CommandRun run(options.threads, quiet);
    ShardPlan plan = planShardedRender(run.environment(scene), options.algorithm, options.settings,
                                       command.shards, scenePath, digest);
    run.finish();
    std::vector<uint8_t> bytes = serializeShardPlan(plan);
    writeFileAtomic(command.out, bytes);
    if (!quiet)
        std::fprintf(stderr, "wrote %s: %s, %u shards, plan %016llx, %zu bytes\n",
                     command.out.c_str(), plan.algorithm.c_str(), plan.shards,
                     static_cast<unsigned long long>(plan.id()), bytes.size());
    return 0;
}

int runShardCommand(const ShardCommand& command, bool quiet) {
    const ShardPlan plan = readPlan(command.plan);
    std::optional<uint32_t> shard = command.shard ? command.shard : shardIndexFromEnvironment();
    if (!shard)
        throw std::invalid_argument(
            "no shard index: give --shard I (or set SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX)");
    requireOutputFolder(command.out);
    RenderScene scene = loadPlannedScene(plan);
    CommandRun run(command.threads, quiet);
    ShardResult result = renderPlannedShard(run.environment(scene), plan, *shard);
    run.finish();
    const auto writeStart = Clock::now();
    const std::vector<uint8_t> bytes = serializeShardResult(result, run.threads());
    writeFileAtomic(command.out, bytes);
    if (!quiet)
        std::fprintf(stderr, "wrote %s: shard %u of %u, %sB in %.2f s\n", command.out.c_str(),
                     *shard, plan.shards, humanCount(double(bytes.size())).c_str(),
                     secondsSince(writeStart));
    return 0;
}

int runMergeCommand(const MergeCommand& command, bool quiet) {
    const ShardPlan plan = readPlan(command.plan);
    requireOutputFolder(command.out);
    std::string png = command.png.empty() ? fs::path(command.out).replace_extension(".png").string()
                                          : command.png;
    requireOutputFolder(png);
    const auto start = Clock::now();
    uint64_t bytesRead = 0;
    ShardMerger merger(plan);
    // Shard files are read and decoded a few at a time on their own threads (decoding is most
    // of a merge), and merged in the order given, so the result is the same.
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    const size_t ahead = std::clamp<size_t>(size_t(cores), 1, 4);
    // The cores not taken by other files' decoding read each file's tiles in parallel.
    const int threadsPerFile =
        std::max(1, cores / int(std::clamp<size_t>(command.shards.size(), 1, ahead)));
    std::deque<std::future<std::pair<ShardResult, uint64_t>>> loading;
    size_t next = 0;
    auto loadMore = [&] {
        while (next < command.shards.size() && loading.size() < ahead) {
            loading.push_back(
                std::async(std::launch::async, [path = command.shards[next], threadsPerFile] {
                    std::vector<uint8_t> bytes = readFileBytes(path);
                    return std::make_pair(deserializeShardResult(bytes, threadsPerFile),
                                          uint64_t(bytes.size()));
                }));
            ++next;
        }
    };
    for (const std::string& path : command.shards) {
        loadMore();
        try {
            auto [result, size] = loading.front().get();
            loading.pop_front();
            bytesRead += size;
            if (!merger.add(std::move(result)) && !quiet)
                std::fprintf(stderr, "%s: that shard was merged already; skipped\n", path.c_str());
        } catch (const std::invalid_argument& e) {
            throw std::runtime_error("'" + path + "': " + e.what());
        }
    }
    if (!merger.complete()) {
        std::string list;
        for (uint32_t i : merger.missing()) list += (list.empty() ? "" : ", ") + std::to_string(i);
        if (!command.allowPartial || merger.mergedCount() == 0)
            throw std::runtime_error("missing shards " + list + " of " +
                                     std::to_string(plan.shards));
        spdlog::warn("partial merge: missing shards {}", list);
    }
    const double mergeSeconds = secondsSince(start);
    RenderScene scene = loadPlannedScene(plan);
    CommandRun run(1, /*quiet=*/true);
    RenderResult result = resolveShardedRender(run.environment(scene), plan, merger.work());
    const double resolveSeconds = secondsSince(start) - mergeSeconds;
    result.stats.values["shards"] = double(plan.shards);
    result.stats.values["shards_merged"] = double(merger.mergedCount());
    writeExr(command.out, result.image,
             describeRender(plan.algorithm, plan.settings, result.stats));
    writePng(png, result.image.combined, autoExposure(result.image.combined));
    const double writeSeconds = secondsSince(start) - mergeSeconds - resolveSeconds;
    if (!quiet)
        std::fprintf(stderr,
                     "wrote %s and %s from %zu of %u shards: read and merged %sB in %.2f s, "
                     "loaded the scene and resolved in %.2f s, wrote in %.2f s\n",
                     command.out.c_str(), png.c_str(), merger.mergedCount(), plan.shards,
                     humanCount(double(bytesRead)).c_str(), mergeSeconds, resolveSeconds,
                     writeSeconds);
    return 0;
}

}  // namespace partita
