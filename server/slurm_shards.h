// A job rendered as a Slurm job array (DESIGN.md "Scale-out"; issue #14): partitad plans the job
// (its start-up runs here, on the daemon's pool), writes the plan into the job's folder in the
// store (a shared file system), submits `sbatch --array=0..N-1` whose tasks run
// `partita-local render --plan`, and follows the array: every shard file that appears is merged
// (ShardMerger: each index once) and the merged image is published as a preview; a task that
// ended without its shard is submitted again once (`sbatch --array=I`), a second failure fails
// the job; a cancel runs `scancel`. The array's id is kept in the folder (state.json), so that
// after a partitad restart the re-queued job finds its array and its shards again instead of
// submitting anew. The result is bit-identical to the one-process render.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "algorithm.h"
#include "cluster_options.h"
#include "shard/sharded_render.h"

namespace partita::server {

struct SlurmJob {
    const ClusterOptions& options;
    std::filesystem::path dir;  // the job's own folder for the plan, the state, shards and logs
    std::string name;           // the array's job name (unique per partitad job)
    std::string tag;            // log prefix
    std::string algorithm;
    RenderSettings settings;
    std::string scenePath;  // a scene file every task can read (shared file system)
    /// Whether the job's cancel came from a daemon shutdown: the array is left running.
    std::function<bool()> shuttingDown;
};

/// Renders `job` through Slurm; throws RenderCancelled when the job's cancel flag is raised
/// (after scancel, unless shutting down), std::runtime_error with one line when Slurm or a shard
/// fails twice.
RenderResult renderOnSlurm(const SlurmJob& job, const ShardEnvironment& env);

/// Removes what renderOnSlurm left in `dir` once the job has ended (the shards, the plan, the
/// state); the tasks' logs stay.
void removeSlurmFiles(const std::filesystem::path& dir);

/// "" when `options` can run: local, or slurm with sbatch, squeue and scancel on the PATH and a
/// worker binary; else one line saying what is missing.
std::string checkSlurmExecutor(const ClusterOptions& options);

/// The partita-local the tasks run: `configured` when set, else beside this partitad
/// (installed), else in the build tree (../tools/local/); "" when none is found.
std::string findShardWorker(const std::string& configured);

}  // namespace partita::server
