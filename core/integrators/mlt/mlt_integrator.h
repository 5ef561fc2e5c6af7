// Path-space Metropolis light transport as an Algorithm ("mlt", Veach & Guibas 1997): a BDPT
// bootstrap gives b and the chains' initial paths (mcmc/bootstrap.h), the chain plan fixes each
// chain's start, random stream and mutation count (mcmc/chain_plan.h), and the chains run
// Veach's four mutations (mcmc/veach_mutations.h) on the thread pool (mcmc/chain_runner.h),
// splatting expected values into per-type layers. The image is I = (b / N) sum h f / f*.
// By default ("direct" = per-pixel) the direct light (L S* E, L D S* E) is estimated per pixel
// apart (direct_light.h) and the chains, with the b of the other paths, are restricted to them;
// the two images add up layer by layer. "direct" = chains leaves every path to the chains.
//
// Orchestration only: budget (mutations per pixel or seconds), progress in the phases
// "bootstrap" and "render", previews, statistics. A perspective camera is required (the
// mutations connect to the pinhole; an orthographic camera's importance is a delta).
#pragma once

#include <memory>

#include "algorithm.h"
#include "clock.h"
#include "integrators/mlt/direct_light.h"
#include "integrators/mlt/mlt_settings.h"
#include "mcmc/chain_plan.h"
#include "mcmc/chain_runner.h"
#include "mcmc/markov_chain.h"
#include "mcmc/veach_mutations.h"

namespace partita {

class BootstrapSampler;
struct BootstrapCandidate;

/// The bootstrap's outcome: b, the candidates, the rays traced.
struct BootstrapResult {
    double b = 0;
    uint64_t samples = 0;
    double sumSquares = 0;  // of the samples' values (b's error: bRelativeVariance)
    std::vector<BootstrapCandidate> candidates;
    uint64_t rays = 0;
};

/// Runs `samples` bootstrap samples on ctx's pool in fixed blocks, in waves merged in block order
/// (deterministic for any thread count), reporting progress in the phase "bootstrap";
/// cancellable. Past `deadline` no further wave starts, and b counts the samples that ran.
BootstrapResult runBootstrap(const RenderContext& ctx, const BootstrapSampler& sampler,
                             uint64_t samples, Deadline deadline = kNoDeadline);

/// The relative variance of the b of the paths `restriction` accepts (all: the bootstrap's b),
/// Var(b) / b^2 = S2 / S1^2 - 1 / N from the N samples' values summed per sample (S1) and their
/// squares (S2); 0 when b is 0.
double bRelativeVariance(const BootstrapResult& bootstrap, const PathRestriction& restriction);

/// The type layers of an mlt render (type_layer_rule.h): the weights are the bootstrap
/// candidates' weight sums per type (each type's share of b).
TypeLayers bootstrapTypeLayers(const RenderSettings& settings,
                               const std::vector<BootstrapCandidate>& candidates);

/// The plan of `chains` chains sharing `mutations` (one group "all" with b), their starts
/// resampled from the bootstrap, their film keeping bootstrapTypeLayers (of every candidate).
/// With a `restriction` (per-pixel direct light: the chains' paths), two groups (the even and
/// the odd chains) have the b of the candidates it accepts and the starts are resampled among
/// those only.
ChainPlan planMltChains(const RenderContext& ctx, const BootstrapSampler& sampler,
                        const BootstrapResult& bootstrap, int chains, uint64_t mutations,
                        const PathRestriction& restriction = {});

/// What mlt does before its chains run: the bootstrap and the chain plan (mutation budgets
/// plan every mutation; a time budget plans an upper bound).
struct MltStart {
    BootstrapResult bootstrap;
    ChainPlan plan;
    double bootstrapSeconds = 0;
    /// Direct light per pixel (settings "direct" = per-pixel): the chains are restricted to
    /// indirect paths in two halves (groups 0 and 1, the even and the odd chains) with their b;
    /// bDirect is the bootstrap's b less the chains'.
    bool directApart = false;
    double bDirect = 0;
    double bRelativeVariance = 0;  // of the chains' b (bRelativeVariance)
};
MltStart startMlt(const RenderContext& ctx, const MltSettings& settings);

/// The chains of a per-pixel-direct render: two halves (even and odd chains, groups 0 and 1)
/// of the same b, in the runner's AllAndHalf layout: `all` holds every chain (with the type
/// layers), `odd` the combined image of the odd chains only.
struct ChainHalves {
    const Film* all = nullptr;
    const Film* odd = nullptr;
    uint64_t mutations[2] = {0, 0};  // of the even and the odd chains
    double b = 0;
    uint64_t mutationsDone() const { return mutations[0] + mutations[1]; }
};
/// Their image: the `all` film scaled by b W H / (all their mutations).
LayeredImage resolveChainHalves(const ChainHalves& chains, const RenderSettings& rs,
                                ThreadPool* pool);

/// The per-pixel direct light of an mlt render (direct_light.h): its renderer (the film), its
/// samples per pixel, and what the split rule measured (negative where it did not run).
struct DirectLightRun {
    std::unique_ptr<DirectLightRenderer> renderer;
    uint64_t spp = 0;
    double variance = -1;    // V_d, per sample per pixel, summed over pixels
    double chainError = -1;  // E_c, of the chains' image
    double timeShare = -1;   // a time budget's: the share of the time the rule gave it
    double pilotRays = 0;    // the pilot's, whose samples are not in the image
    double seconds = 0;
    /// Every ray the direct light traced, the pilot's included.
    double rays() const { return (renderer ? double(renderer->rays()) : 0) + pilotRays; }
};

/// What the direct light after the chains needs of them, taken from their films so that the
/// films may go before the direct light's are made: the type layers, and for the split rule
/// (settings.directSpp = 0) the chains' error E_c (chainHalvesError; else negative).
struct ChainsForDirect {
    TypeLayers layers;
    double error = -1;
};
ChainsForDirect chainsForDirect(const MltSettings& settings, const ChainHalves& chains,
                                const RenderSettings& rs);

/// A mutation budget's direct light once its chains are done, in process and in a sharded
/// job's resolve alike (the same film and samples per pixel: bit-identical): settings.directSpp
/// samples per pixel, or with 0 as many as neymanDirectSpp gives from the pilot's variance and
/// rays (`pilot` when it already ran, else run here), the chains' error and `chainRays`. With
/// `keepHalves` the renderer keeps its error estimate's halves (DirectLightRenderer::keepHalves:
/// the samples in two passes, the same film).
DirectLightRun directLightAfterChains(const RenderContext& ctx, const MltSettings& settings,
                                      const ChainsForDirect& chains, double chainRays,
                                      const DirectPilot* pilot, bool keepHalves = false);

/// The statistics of the direct light: the label "direct" (per-pixel or chains), direct_spp,
/// and when apart b_direct, direct_rays, direct_share (of the rays after the bootstrap), and
/// the rule's direct_variance, chain_error and (time budgets) direct_time_share.
void addDirectLightStats(RenderStats& st, bool apart, const DirectLightRun& direct, double bDirect,
                         double chainRays);

/// The chains' films: per group, or with the direct light apart all chains and the odd half.
ChainRunner::FilmLayout mltFilmLayout(bool directApart);

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
