// Where partitad renders its jobs (DESIGN.md "Scale-out"): in this process ("local", the
// default), or as shards of a Slurm job array ("slurm") that partitad plans, submits, follows,
// merges, retries once per shard and cancels (slurm_shards.h).
#pragma once

#include <string>

namespace partita::server {

struct ClusterOptions {
    std::string executor = "local";  // "local" or "slurm"
    int shards = 8;                  // shards of a job (fewer when the plan has less work)
    int cpusPerTask = 1;             // sbatch --cpus-per-task, and the worker's --threads
    std::string worker;              // the partita-local binary the tasks run; empty: beside
                                     // partitad (installed) or in the build tree
    std::string partition;           // sbatch --partition; empty: the cluster's default
    double pollSeconds = 1.0;        // how often squeue and the shard files are looked at
    bool slurm() const { return executor == "slurm"; }
};

}  // namespace partita::server
