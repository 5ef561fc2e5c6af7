#include "integrators/mlt/mlt_integrator.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>

#include "camera.h"
#include "clock.h"
#include "integrators/mlt/direct_light.h"
#include "integrators/mlt/mlt_shards.h"
#include "mcmc/bootstrap.h"
#include "mcmc/chain_error_monitor.h"
#include "mcmc/chain_render.h"
#include "mcmc/chain_runner.h"
#include "mcmc/startup_parameters.h"
#include "mcmc/startup_rule.h"
#include "path/path.h"
#include "progress_reporter.h"
#include "render_scene.h"
#include "sample_waves.h"
#include "share_range.h"
#include "thread_pool.h"
#include "type_layer_rule.h"

namespace partita {

namespace {

constexpr uint64_t kBootstrapBlock = 256;
constexpr uint64_t kResampleStream = 0x52534d50ull;        // "RSMP"
constexpr uint64_t kChainStreams = 0x434841494eull << 24;  // "CHAIN"

}  // namespace

BootstrapResult runBootstrap(const RenderContext& ctx, const BootstrapSampler& sampler,
                             uint64_t samples, Deadline deadline) {
    ProgressReporter progress(ctx.observer, "bootstrap", "samples", double(samples));
    struct Block {
        std::vector<BootstrapCandidate> candidates;
        double sum = 0, squares = 0;
        uint64_t rays = 0;
    };
    auto run = [&](uint64_t k, Block& block) {
        uint64_t first = k * kBootstrapBlock, end = std::min(samples, first + kBootstrapBlock);
        for (uint64_t i = first; i < end; ++i) {
            if ((i & 15) == 0) ctx.throwIfCancelled();
            const double value = sampler.sample(i, block.candidates, block.rays);
            block.sum += value;
            block.squares += value * value;
        }
        progress.advance(double(end - first));
    };
    BootstrapResult r;
    // Room for the candidates the samples are expected to leave: the list does not double past
    // them (what is reserved and not touched costs no memory).
    // (At most 2^24 records, 640 MiB of address space: a larger bootstrap grows as it goes.)
    r.candidates.reserve(size_t(std::min(double(samples) * kCandidatesPerSample, 16777216.0)));
    double sum = 0;
    auto merge = [&](Block& block) {  // in block order: the same sums for any thread count
        sum += block.sum;
        r.sumSquares += block.squares;
        r.rays += block.rays;
        r.candidates.insert(r.candidates.end(), block.candidates.begin(), block.candidates.end());
    };
    uint64_t blocks = (samples + kBootstrapBlock - 1) / kBootstrapBlock;
    uint64_t ran =
        runInWaves<Block>(ctx.pool, blocks, run, merge, [&] { return Clock::now() >= deadline; });
    progress.flush();
    r.samples = std::min(samples, ran * kBootstrapBlock);
    r.b = r.samples > 0 ? sum / double(r.samples) : 0;
    return r;
}

double bRelativeVariance(const BootstrapResult& bootstrap, const PathRestriction& restriction) {
    double s1 = 0, s2 = restriction ? 0 : bootstrap.sumSquares;
    if (!restriction) {
        s1 = bootstrap.b * double(bootstrap.samples);
    } else {
        // The candidates come in sample order: sum the accepted ones sample by sample.
        double sample = 0;
        uint64_t index = UINT64_MAX;
        for (const BootstrapCandidate& c : bootstrap.candidates) {
            if (!restriction(c.type)) continue;
            if (c.sample != index) {
                s2 += sample * sample;
                sample = 0;
                index = c.sample;
            }
            sample += double(c.weight);
            s1 += double(c.weight);
        }
        s2 += sample * sample;
    }
    if (!(s1 > 0) || bootstrap.samples == 0) return 0;
    return relativeVarianceOfMean(s1, s2, double(bootstrap.samples));
}

TypeLayers bootstrapTypeLayers(const RenderSettings& settings,
                               const std::vector<BootstrapCandidate>& candidates) {
    std::map<PathType, double> weights;
    if (needsTypeWeights(settings))
        for (const BootstrapCandidate& c : candidates) weights[c.type] += double(c.weight);
    return chooseTypeLayers(settings, weights);
}

ChainPlan planMltChains(const RenderContext& ctx, const BootstrapSampler& sampler,
                        const BootstrapResult& bootstrap, int chains, uint64_t mutations,
                        const PathRestriction& restriction) {
    ChainPlan plan;
    plan.seed = ctx.settings.seed;
    plan.bootstrapSamples = bootstrap.samples;
    // The types both parts keep a layer of (the direct light's film and the chains'), from every
    // candidate: a type is in one part only, so a type of the sum's top is in its part's top.
    plan.layers = bootstrapTypeLayers(ctx.settings, bootstrap.candidates);
    Rng rng(ctx.settings.seed, kResampleStream);
    // The candidates the chains may start from, their b and the drawn starts. Unrestricted: all
    // of them, with the bootstrap's b (the plan as before the restriction existed, bit for bit).
    std::vector<uint32_t> members;
    std::vector<size_t> starts;
    if (!restriction) {
        plan.groups.push_back({"all", bootstrap.b});
        starts = resampleCandidates(bootstrap.candidates, size_t(chains), rng);
    } else {
        // b of the part of path space the chains may visit: the bootstrap's estimator summed
        // over the candidates of its types only (in candidate order: deterministic).
        double sum = 0;
        for (size_t i = 0; i < bootstrap.candidates.size(); ++i)
            if (restriction(bootstrap.candidates[i].type)) {
                members.push_back(uint32_t(i));
                sum += bootstrap.candidates[i].weight;
            }
        // Two groups of the same b, the even and the odd chains: two independent halves, whose
        // difference measures the chains' error (direct_light.h's split rule).
        const double b = bootstrap.samples > 0 ? sum / double(bootstrap.samples) : 0;
        plan.groups.push_back({"indirect-even", b});
        plan.groups.push_back({"indirect-odd", b});
        starts = resampleCandidates(bootstrap.candidates, members, size_t(chains), rng);
        for (size_t& start : starts) start = members[start];
    }
    for (size_t k = 0; k < starts.size(); ++k) {
        std::vector<uint8_t> start =
            chainStart(ctx, sampler, bootstrap.candidates, starts[k], restriction);
        if (start.empty()) continue;
        PlannedChain chain;
        chain.group = restriction ? uint32_t(k % 2) : 0;
        chain.stream = kChainStreams + k;
        chain.mutations = shareRange(mutations, starts.size(), k).count();
        chain.start = std::move(start);
        plan.chains.push_back(std::move(chain));
    }
    return plan;
}

MltStart startMlt(const RenderContext& ctx, const MltSettings& settings) {
    const RenderSettings& rs = ctx.settings;
    if (!ctx.camera.isConnectable())
        throw std::invalid_argument(
            "mlt needs a perspective camera (its mutations connect paths "
            "to the pinhole; an orthographic camera cannot be reached)");
    auto start = Clock::now();
    bool timed = rs.budgetKind == BudgetKind::Seconds;
    double pixels = double(rs.width) * rs.height;
    uint64_t mutations = timed ? UINT64_MAX / 4 : uint64_t(rs.budget * pixels);

    BootstrapSampler sampler(ctx.scene, ctx.camera, rs.maxDepth, rs.seed);
    MltStart out;
    out.bootstrap =
        runBootstrap(ctx, sampler, StartupRule::bootstrapSamples(settings.bootstrapSamples, rs),
                     startupDeadline(rs, start, settings.startupShare));
    out.bootstrapSeconds = secondsSince(start);
    ctx.throwIfCancelled();

    uint64_t byBudget = std::max<uint64_t>(1, mutations / settings.minMutationsPerChain);
    int chains = int(std::min<uint64_t>(uint64_t(std::max(1, settings.chains)), byBudget));
    out.directApart = settings.direct != "chains";
    out.plan = planMltChains(ctx, sampler, out.bootstrap, chains, mutations,
                             out.directApart ? indirectLightOnly() : PathRestriction{});
    if (out.directApart) out.bDirect = out.bootstrap.b - out.plan.groups[0].b;
    out.bRelativeVariance =
        bRelativeVariance(out.bootstrap, out.directApart ? indirectLightOnly() : PathRestriction{});
    return out;
}

ChainRunner::FilmLayout mltFilmLayout(bool directApart) {
    return directApart ? ChainRunner::FilmLayout::AllAndHalf : ChainRunner::FilmLayout::PerGroup;
}

MutationSet makeMltMutations(const RenderContext& ctx, const MltSettings& settings) {
    VeachMutationSettings m = settings.mutations;
    // With the direct light apart the chains hold no path of 2 or 3 vertices (every one is
    // L S? E or L D E): the independence mutation does not propose them.
    if (settings.direct != "chains" && m.independenceVertexCounts.empty())
        for (int n = 4; n <= ctx.settings.maxDepth + 2; ++n)
            m.independenceVertexCounts.push_back(n);
    return makeVeachMutations(ctx.scene, ctx.camera, ctx.settings.maxDepth, m);
}

LayeredImage resolveChainHalves(const ChainHalves& chains, const RenderSettings& rs,
                                ThreadPool* pool) {
    return chains.all->resolve(
        ChainRunner::filmScale(chains.b, rs.width, rs.height, chains.mutationsDone()),
        rs.maxTypeLayers, pool);
}

ChainsForDirect chainsForDirect(const MltSettings& settings, const ChainHalves& chains,
                                const RenderSettings& rs) {
    ChainsForDirect out{chains.all->layers()};
    if (settings.directSpp == 0)
        out.error = chainHalvesError(*chains.all, *chains.odd, chains.mutations[0],
                                     chains.mutations[1], chains.b, rs.width, rs.height);
    return out;
}

DirectLightRun directLightAfterChains(const RenderContext& ctx, const MltSettings& settings,
                                      const ChainsForDirect& chains, double chainRays,
                                      const DirectPilot* pilot, bool keepHalves) {
    auto begin = Clock::now();
    const double pilotSeconds = pilot ? pilot->seconds : 0;  // ran before
    DirectLightRun out;
    uint64_t spp = settings.directSpp;
    const bool byRule = spp == 0;
    const uint64_t minSpp = std::max<uint64_t>(2, settings.directMinSpp);
    const uint64_t maxSpp = std::max(minSpp, settings.directMaxSpp);
    DirectPilot own;
    if (byRule) {
        if (!pilot) {
            own = runDirectPilot(ctx, nullptr);
            pilot = &own;
        }
        out.variance = pilot->variance;
        out.pilotRays = pilot->rays;
        out.chainError = chains.error;
        // Costs in rays: c_d of one sample per pixel (the pilot's two), T_c the chains'.
        spp = neymanDirectSpp(out.variance, pilot->rays / 2, out.chainError, chainRays, minSpp,
                              maxSpp);
    }
    out.renderer = std::make_unique<DirectLightRenderer>(ctx, chains.layers);
    // No progress reports: the render phase's last report stays the chains' (mutations). With
    // the halves, two passes (the same film as one: every sample has its own stream and the
    // sums are exact). The rule re-reads V_d from them, so it always keeps them.
    keepHalves = keepHalves || byRule;
    const uint64_t firstPass = keepHalves ? spp / 2 : spp;
    if (keepHalves) out.renderer->keepHalves();
    out.renderer->renderPass({0, firstPass}, nullptr);
    out.renderer->renderPass({firstPass, spp}, nullptr);
    // The rule again with V_d pooled from the pilot and the samples so far (what the pilot's
    // two samples missed: pooledDirectVariance), at most doubling the samples at a time so
    // that each step reads an estimate of the samples before it. Deterministic: the samples
    // alone decide, so a sharded job's resolve renders the same.
    while (byRule && spp < maxSpp) {
        out.variance = pooledDirectVariance(pilot->variance, out.renderer->halves());
        const uint64_t wanted = neymanDirectSpp(out.variance, pilot->rays / 2, out.chainError,
                                                chainRays, minSpp, maxSpp);
        if (wanted <= spp) break;
        ctx.throwIfCancelled();
        const uint64_t next = std::min(wanted, 2 * spp);
        out.renderer->renderPass({spp, next}, nullptr);
        spp = next;
    }
    out.spp = spp;
    out.seconds = secondsSince(begin) + pilotSeconds;
    return out;
}

void addDirectLightStats(RenderStats& st, bool apart, const DirectLightRun& direct, double bDirect,
                         double chainRays) {
    st.labels["direct"] = apart ? "per-pixel" : "chains";
    st.values["direct_spp"] = double(direct.spp);
    if (!apart) return;
    const double directRays = direct.rays();
    st.values["b_direct"] = bDirect;
    st.values["direct_rays"] = directRays;
    // The share of the rays after the bootstrap that went to the per-pixel direct light.
    st.values["direct_share"] =
        directRays + chainRays > 0 ? directRays / (directRays + chainRays) : 0;
    // The split rule's inputs (direct_light.h), when it chose the samples per pixel.
    if (direct.variance >= 0) st.values["direct_variance"] = direct.variance;
    if (direct.chainError >= 0) st.values["chain_error"] = direct.chainError;
    if (direct.timeShare >= 0) st.values["direct_time_share"] = direct.timeShare;
}

namespace {

/// With a target error E and a part of the image that renders apart (mlt's chains and its
/// direct light after them), each part gets half of E^2: the value compared with E is
/// sqrt(2 Var_part / count) / mean of the whole image (`total`).
double sharedTargetValue(const ErrorSums& part, const ErrorSums& total) {
    if (!(part.count > 0) || !(total.value > 0)) return INFINITY;
    return std::sqrt(2 * part.variance / part.count) / (total.value / total.count);
}

/// A mutation budget's direct light after its chains, with a target error E: its share of
/// it, half of E^2 as the chains' (sharedTargetValue), from its own halves: more samples,
/// doubling, until it is met or the direct light has `maxSpp`. `chains`: the chains' error.
void renderDirectToTarget(const RenderContext& ctx, DirectLightRun& direct, const ErrorSums& chains,
                          double targetError, uint64_t maxSpp) {
    auto begin = Clock::now();
    while (direct.spp < maxSpp) {
        const ErrorSums own = direct.renderer->halves().errorSums();
        ErrorSums total;
        total.add(chains);
        total.add(own);
        if (sharedTargetValue(own, total) <= targetError) break;
        ctx.throwIfCancelled();
        const uint64_t next = std::min(maxSpp, 2 * direct.spp);
        direct.renderer->renderPass({direct.spp, next}, nullptr);
        direct.spp = next;
    }
    direct.seconds += secondsSince(begin);
}

/// Runs the chains for `seconds` (a time budget's stage) after `startupSeconds` of the job.
void runChainsFor(const RenderContext& ctx, ChainRunner& runner, const ChainPlan& plan,
                  double startupSeconds, double seconds,
                  const std::function<LayeredImage(ThreadPool*)>& resolve,
                  const std::function<void(ProgressReporter&)>& afterRound) {
    RenderSettings stage = ctx.settings;
    stage.budget = startupSeconds + seconds;
    RenderContext stageCtx{ctx.scene, ctx.camera, stage, ctx.pool, ctx.cancel, ctx.observer};
    runChainsWithPreviews(stageCtx, runner, plan, startupSeconds, resolve, {}, afterRound);
}

/// A time budget's fixed direct light before the chains: settings.directSpp samples per pixel,
/// stopping once it has had directShare of the time the bootstrap left.
DirectLightRun fixedDirectLightFirst(const RenderContext& ctx, const MltSettings& settings,
                                     const TypeLayers& layers, double startupSeconds) {
    auto begin = Clock::now();
    const RenderSettings& rs = ctx.settings;
    DirectLightRun out;
    out.renderer = std::make_unique<DirectLightRenderer>(ctx, layers);
    out.renderer->keepHalves();  // the error estimate's
    const double limit = std::max(0.0, rs.budget - startupSeconds) * settings.directShare;
    ProgressReporter progress(ctx.observer, "render", "samples", 0);
    while (out.spp < settings.directSpp) {
        ctx.throwIfCancelled();
        out.renderer->renderPass({out.spp, out.spp + 1}, &progress);
        ++out.spp;
        if (secondsSince(begin) >= limit) break;
    }
    progress.flush();
    out.seconds = secondsSince(begin);
    return out;
}

/// A time budget's direct light after the chains' first stage (which cost `chainSeconds`): passes
/// of about a quarter of a second until it has had the rule's share of `total` (the time after
/// the bootstrap), the share recomputed after every pass with V_d pooled from the pilot and the
/// samples so far (pooledDirectVariance) and the passes' own cost; at least one sample per pixel
/// whatever the share (the chains never see direct paths) and, while the budget lasts, at least
/// settings.directMinSpp (the variance is read from them). Sets direct's spp, variance, seconds
/// (the pilot's included) and timeShare.
void renderDirectForShare(const RenderContext& ctx, const MltSettings& settings,
                          DirectLightRun& direct, const DirectPilot& pilot, double chainSeconds,
                          double total, Clock::time_point start) {
    const double budget = ctx.settings.budget;
    const uint64_t minSpp = std::max<uint64_t>(1, settings.directMinSpp);
    double perSpp = pilot.seconds / 2;
    double share = neymanDirectShare(direct.variance, perSpp, direct.chainError, chainSeconds);
    double directSeconds = pilot.seconds, passSeconds = 0;
    ProgressReporter progress(ctx.observer, "render", "samples", 0);
    while (direct.spp == 0 || (direct.spp < (uint64_t(1) << 20) && secondsSince(start) < budget &&
                               (direct.spp < minSpp || directSeconds < share * total))) {
        ctx.throwIfCancelled();
        // Never past the share, but to the fewest samples; the first pass is one half's
        // (passes alternate between the two): at most half the fewest, so that both halves hold
        // samples when the variance is first read.
        const double left = std::min(share * total - directSeconds, 0.25);
        const double toMin = double(minSpp) - double(direct.spp);
        uint64_t n =
            uint64_t(std::clamp(std::max(toMin, left / std::max(perSpp, 1e-9)), 1.0, 4096.0));
        if (direct.spp == 0) n = std::min(n, std::max<uint64_t>(1, minSpp / 2));
        auto passStart = Clock::now();
        direct.renderer->renderPass({direct.spp, direct.spp + n}, &progress);
        direct.spp += n;
        passSeconds += secondsSince(passStart);
        directSeconds = pilot.seconds + passSeconds;
        direct.variance = pooledDirectVariance(pilot.variance, direct.renderer->halves());
        perSpp = passSeconds / double(direct.spp);
        share = neymanDirectShare(direct.variance, perSpp, direct.chainError, chainSeconds);
    }
    progress.flush();
    direct.seconds = directSeconds;
    direct.timeShare = share;
}

}  // namespace

RenderResult MltAlgorithm::render(const RenderContext& ctx) {
    const RenderSettings& rs = ctx.settings;
    auto start = Clock::now();
    const double pixels = double(rs.width) * rs.height;
    const bool timed = rs.budgetKind == BudgetKind::Seconds;
    MltStart mltStart = startMlt(ctx, settings_);
    const BootstrapResult& bootstrap = mltStart.bootstrap;
    const ChainPlan& plan = mltStart.plan;
    const double bootstrapSeconds = mltStart.bootstrapSeconds;
    const bool apart = mltStart.directApart;
    auto makeMutations = [&](uint32_t) { return makeMltMutations(ctx, settings_); };
    ChainRunner::RestrictionFactory restrictions;
    if (apart) restrictions = [](uint32_t) { return indirectLightOnly(); };
    // With every path in the chains, their odd half gets a film of its own (the error estimate).
    ChainRunner runner(
        ctx, plan, makeMutations, restrictions, settings_.roundMutations,
        apart ? ChainRunner::FilmLayout::AllAndHalf : ChainRunner::FilmLayout::PerGroupWithHalves);
    ChainHalves halves;
    if (apart) halves = {&runner.film(0), &runner.film(1), {0, 0}, plan.groups[0].b};
    auto countHalves = [&] {
        halves.mutations[0] = runner.mutationsDone(0);
        halves.mutations[1] = runner.mutationsDone(1);
    };
    auto chainImage = [&](ThreadPool* pool) {
        if (!apart) return runner.resolveGroup(0, pool);
        countHalves();
        return resolveChainHalves(halves, rs, pool);
    };
    // What the previews show of the direct light: its pilot, then all of it.
    LayeredImage directImage;
    auto resolve = [&](ThreadPool* pool) {
        LayeredImage chains = chainImage(pool);
        return apart ? addDisjointParts(directImage, std::move(chains), rs.maxTypeLayers) : chains;
    };

    // The error estimate (issue #26): the chains' two halves with b's error and, with the
    // direct light apart, the direct image's: its pilot's two samples until the direct light
    // proper has run, then that one's own halves.
    ErrorSums pilotError;
    const DirectLightRenderer* directRenderer = nullptr;
    auto directError = [&]() -> ErrorSums {
        if (directRenderer && directRenderer->halves().ready())
            return directRenderer->halves().errorSums();
        return pilotError;
    };
    // A mutation budget renders the direct light after the chains, with as many samples as
    // the target needs (below): its chains stop on their own share of the target, half the
    // squared error, of the image with the direct light as far as it has run.
    const bool directAfterChains = apart && !timed;
    // Once the chains are done with a mutation budget, their error is taken before the direct
    // light runs, so that the odd half's film can go first.
    std::optional<ErrorSums> chainsDoneError;
    auto chainsError = [&] {
        if (chainsDoneError) return *chainsDoneError;
        ErrorSums chains = runner.halvesError(0);
        chains.addScaleVariance(mltStart.bRelativeVariance);
        return chains;
    };
    ChainErrorMonitor monitor(rs, settings_.targetError, [&] {
        ChainErrorMonitor::Estimate estimate;
        const ErrorSums chains = chainsError();
        if (!(chains.count > 0)) return estimate;
        ErrorSums total;
        total.add(chains);
        if (apart) {
            const ErrorSums direct = directError();
            if (!(direct.count > 0)) {
                if (directAfterChains) estimate.target = sharedTargetValue(chains, chains);
                return estimate;
            }
            total.add(direct);
            if (directAfterChains) estimate.target = sharedTargetValue(chains, total);
        }
        estimate.combined = total.relativeRmse();
        return estimate;
    });
    auto afterRound = [&](ProgressReporter& progress) { monitor.afterRound(runner, progress); };

    DirectLightRun direct;
    double startupSeconds = bootstrapSeconds;
    if (!apart) {
        runChainsWithPreviews(ctx, runner, plan, startupSeconds, resolve, {}, afterRound);
    } else if (settings_.directSpp > 0 && timed) {
        // A fixed count first, then the chains with the time left.
        direct = fixedDirectLightFirst(ctx, settings_, plan.layers, bootstrapSeconds);
        startupSeconds += direct.seconds;
        directImage =
            resolveDirectLight(direct.renderer->film(), direct.spp, rs.maxTypeLayers, &ctx.pool);
        directRenderer = direct.renderer.get();
        runChainsWithPreviews(ctx, runner, plan, startupSeconds, resolve, {}, afterRound);
    } else {
        // The pilot's two samples per pixel first (the previews' direct light).
        DirectPilot pilot;
        if (settings_.directSpp == 0) {
            ProgressReporter pilotProgress(ctx.observer, "render", "samples", 2 * pixels);
            pilot = runDirectPilot(ctx, &pilotProgress);
            pilotProgress.flush();
            directImage.combined = std::move(pilot.image);
            startupSeconds += pilot.seconds;
            pilotError = pilot.errorSums;
        }
        if (!timed) {
            // A mutation budget: all the chains, then the direct light the rule gives them.
            runChainsWithPreviews(ctx, runner, plan, startupSeconds, resolve, {}, afterRound);
            countHalves();
            // What the rest needs of the odd half's film is taken now and the film let go, and
            // the previews' direct light with it, before the direct light makes its two films
            // (with --layers 0 each is 24 B a pixel, the image 12: 50 and 25 MB at 1080p).
            const ChainsForDirect chainsDone = chainsForDirect(settings_, halves, rs);
            chainsDoneError = chainsError();
            runner.takeFilm(1);
            halves.odd = nullptr;
            directImage = {};
            direct = directLightAfterChains(ctx, settings_, chainsDone, double(runner.rays()),
                                            settings_.directSpp == 0 ? &pilot : nullptr,
                                            /*keepHalves=*/true);
            directRenderer = direct.renderer.get();
            if (settings_.targetError > 0)
                renderDirectToTarget(ctx, direct, chainsError(), settings_.targetError,
                                     settings_.directMaxSpp);
            startupSeconds = bootstrapSeconds + direct.seconds;
        } else {
            // A time budget: the chains' first stage measures their error and cost in seconds,
            // the rule splits the time after the bootstrap, the direct light takes its share
            // and the chains the rest.
            const double total = std::max(0.0, rs.budget - bootstrapSeconds);
            const double first =
                settings_.firstChainShare * std::max(0.0, rs.budget - secondsSince(start));
            auto chainsStart = Clock::now();
            runChainsFor(ctx, runner, plan, secondsSince(start), first, resolve, afterRound);
            const double chainSeconds = secondsSince(chainsStart);
            countHalves();
            direct.renderer = std::make_unique<DirectLightRenderer>(ctx, plan.layers);
            direct.renderer->keepHalves();
            direct.variance = pilot.variance;
            direct.pilotRays = pilot.rays;
            direct.chainError =
                chainHalvesError(*halves.all, *halves.odd, halves.mutations[0], halves.mutations[1],
                                 halves.b, rs.width, rs.height);
            renderDirectForShare(ctx, settings_, direct, pilot, chainSeconds, total, start);
            directImage = resolveDirectLight(direct.renderer->film(), direct.spp, rs.maxTypeLayers,
                                             &ctx.pool);
            directRenderer = direct.renderer.get();
            startupSeconds = bootstrapSeconds + direct.seconds;
            const double elapsed = secondsSince(start);
            // A target reached in the first stage leaves the chains one more round.
            runChainsFor(ctx, runner, plan, elapsed, std::max(0.0, rs.budget - elapsed), resolve,
                         afterRound);
        }
    }
    size_t directTypes = 0;
    if (apart) {
        directImage =
            resolveDirectLight(direct.renderer->film(), direct.spp, rs.maxTypeLayers, &ctx.pool);
        directTypes = direct.renderer->film().typeCount();
        directRenderer = direct.renderer.get();
    }
    monitor.estimateNow();  // the final image's (before the films are consumed)

    RenderResult result;
    RenderStats& st = result.stats;
    st.values["b"] = plan.groups[0].b;
    st.values["bootstrap_samples"] = double(bootstrap.samples);
    st.values["bootstrap_seconds"] = bootstrapSeconds;
    st.values["bootstrap_rays"] = double(bootstrap.rays);
    const double directRays = direct.rays();
    st.values["path_types"] = double(runner.film(0).typeCount() + directTypes);
    addChainStats(st, runner, plan, secondsSince(start), startupSeconds,
                  bootstrap.rays + uint64_t(directRays), pixels);
    addDirectLightStats(st, apart, direct, mltStart.bDirect, double(runner.rays()));
    if (apart) st.values["direct_seconds"] = direct.seconds;
    monitor.addStats(st);
    // Last: the chains' image consumes their film (its memory given back layer by layer); with
    // the direct light apart, the direct film and the odd half's are let go first (their parts
    // are made): the same image as resolve(), with two films fewer at the peak.
    if (!apart) {
        result.image = runner.takeResolvedGroup(0, &ctx.pool);
        return result;
    }
    direct.renderer.reset();
    countHalves();
    runner.takeFilm(1);
    Film all = runner.takeFilm(0);
    LayeredImage chains = all.takeResolved(
        ChainRunner::filmScale(halves.b, rs.width, rs.height, halves.mutationsDone()),
        rs.maxTypeLayers, &ctx.pool);
    result.image = addDisjointParts(std::move(directImage), std::move(chains), rs.maxTypeLayers);
    return result;
}

MltAlgorithm::MltAlgorithm(MltSettings settings) : settings_(settings) {}
MltAlgorithm::~MltAlgorithm() = default;

Shardable* MltAlgorithm::shardable() {
    if (!shards_) shards_ = std::make_unique<MltShards>(settings_);
    return shards_.get();
}

void registerMlt() {
    AlgorithmRegistry::instance().add(algorithmEntry<MltAlgorithm>(
        "mlt",
        "path-space Metropolis light transport (Veach & Guibas 1997): BDPT bootstrap, "
        "bidirectional, lens, caustic and multi-chain mutations; per-type layers",
        BudgetKind::MutationsPerPixel, mltParameters(), /*orthographicCamera=*/false));
}

}  // namespace partita
