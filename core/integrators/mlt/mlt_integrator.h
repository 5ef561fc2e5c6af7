// Path-space Metropolis light transport as an Algorithm ("mlt", Veach & Guibas 1997): a BDPT
// bootstrap gives b and the chains' initial paths (mcmc/bootstrap.h), the chain plan fixes each
// chain's start, random stream and mutation count (mcmc/chain_plan.h), and the chains run
// Veach's four mutations (mcmc/veach_mutations.h) on the thread pool (mcmc/chain_runner.h),
// splatting expected values into per-type layers. The image is I = (b / N) sum h f / f*.
//
// Orchestration only: budget (mutations per pixel or seconds), progress in the phases
// "bootstrap" and "render", previews, statistics. A perspective camera is required (the
// mutations connect to the pinhole; an orthographic camera's importance is a delta).
#pragma once

#include <memory>

#include "algorithm.h"
#include "clock.h"
#include "integrators/mlt/mlt_settings.h"
#include "mcmc/chain_plan.h"
#include "mcmc/veach_mutations.h"

namespace partita {

class BootstrapSampler;
struct BootstrapCandidate;

/// The bootstrap's outcome: b, the candidates, the rays traced.
struct BootstrapResult {
    double b = 0;
    uint64_t samples = 0;
    std::vector<BootstrapCandidate> candidates;
    uint64_t rays = 0;
};

/// Runs `samples` bootstrap samples on ctx's pool in fixed blocks, in waves merged in block order
/// (deterministic for any thread count), reporting progress in the phase "bootstrap";
/// cancellable. Past `deadline` no further wave starts, and b counts the samples that ran.
BootstrapResult runBootstrap(const RenderContext& ctx, const BootstrapSampler& sampler,
                             uint64_t samples, Deadline deadline = kNoDeadline);

/// The type layers of an mlt render (type_layer_rule.h): the weights are the bootstrap
/// candidates' weight sums per type (each type's share of b).
TypeLayers bootstrapTypeLayers(const RenderSettings& settings,
                               const std::vector<BootstrapCandidate>& candidates);

/// The plan of `chains` chains sharing `mutations` (one group "all" with b), their starts
/// resampled from the bootstrap, their film keeping bootstrapTypeLayers.
ChainPlan planMltChains(const RenderContext& ctx, const BootstrapSampler& sampler,
                        const BootstrapResult& bootstrap, int chains, uint64_t mutations);

/// What mlt does before its chains run: the bootstrap and the chain plan (mutation budgets
/// plan every mutation; a time budget plans an upper bound).
struct MltStart {
    BootstrapResult bootstrap;
    ChainPlan plan;
    double bootstrapSeconds = 0;
};
MltStart startMlt(const RenderContext& ctx, const MltSettings& settings);

/// One chain's mutations.
MutationSet makeMltMutations(const RenderContext& ctx, const MltSettings& settings);

class MltAlgorithm : public Algorithm {
  public:
    explicit MltAlgorithm(MltSettings settings = {});
    ~MltAlgorithm() override;
    RenderResult render(const RenderContext& ctx) override;
    Shardable* shardable() override;

  private:
    MltSettings settings_;
    std::unique_ptr<Shardable> shards_;
};

void registerMlt();

}  // namespace partita
