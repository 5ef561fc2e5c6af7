// What every MCMC Algorithm (mlt, partitioned, guided) does around its chains, written once:
// running the runner in the phase "render" under the job's budget with previews and progress,
// choosing a chain's start among start-up candidates, and the statistics they all report.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "algorithm.h"
#include "mcmc/bootstrap.h"
#include "mcmc/chain_plan.h"
#include "mcmc/chain_runner.h"

namespace partita {

/// Runs `runner` (phase "render", progress in mutations) under ctx's budget: all the plan's
/// mutations, or the time left after a start-up of `startupSeconds`. A preview at the first
/// round's end and then once per preview interval: resolve(pool) and addStats(stats). After
/// every round, afterRound(progress) (when set) may add to the phase's next report, e.g. its
/// partitions (ProgressReporter::setPartitions).
void runChainsWithPreviews(const RenderContext& ctx, ChainRunner& runner, const ChainPlan& plan,
                           double startupSeconds,
                           const std::function<LayeredImage(ThreadPool*)>& resolve,
                           const std::function<void(RenderStats&)>& addStats,
                           const std::function<void(ProgressReporter&)>& afterRound = {});

/// The first candidate from index `first` on whose recorded type and whose path, regenerated,
/// serialised and rebuilt, carries something (f* > 0) and are accepted by `accept` (empty: any):
/// its serialised bytes,
/// or empty when none is (a path whose f* rounds to 0 once rebuilt gives its chain to the next).
std::vector<uint8_t> chainStart(const RenderContext& ctx, const BootstrapSampler& sampler,
                                const std::vector<BootstrapCandidate>& candidates, size_t first,
                                const PathRestriction& accept = {});

/// chains, mutations, mpp, seconds, render_seconds, mutations_per_second, rays, rays_per_second,
/// and proposed_<mutation> and acceptance_<mutation> per mutation.
void addChainStats(RenderStats& st, const ChainRunner& runner, const ChainPlan& plan,
                   double seconds, double startupSeconds, uint64_t startupRays, double pixels);

}  // namespace partita
