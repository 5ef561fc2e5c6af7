// partita-local's scale-out commands (DESIGN.md "Scale-out"):
//   partita-local plan SCENE --shards N --out PLAN [render options]
//   partita-local render --plan PLAN [--shard I] --out SHARD
//       (I defaults to $SLURM_ARRAY_TASK_ID, then $JOB_COMPLETION_INDEX)
//   partita-local merge --plan PLAN SHARD... --out FILE.exr [--png FILE.png] [--allow-partial]
// Each exits non-zero with one clear line on a wrong, missing or mismatched shard.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "frontend/render_options.h"

namespace partita {

struct PlanCommand {
    std::string scene, out;
    uint32_t shards = 1;
};
int runPlanCommand(const PlanCommand& command, RenderOptions& options, bool quiet);

struct ShardCommand {
    std::string plan, out;
    std::optional<uint32_t> shard;
    int threads = 0;
};
int runShardCommand(const ShardCommand& command, bool quiet);

struct MergeCommand {
    std::string plan, out, png;
    std::vector<std::string> shards;
    bool allowPartial = false;
};
int runMergeCommand(const MergeCommand& command, bool quiet);

/// The shard index from the environment: SLURM_ARRAY_TASK_ID, else JOB_COMPLETION_INDEX.
std::optional<uint32_t> shardIndexFromEnvironment();

}  // namespace partita
