#include "integrators/mlt/mlt_integrator.h"

#include <algorithm>
#include <stdexcept>

#include "camera.h"
#include "clock.h"
#include "integrators/mlt/direct_light.h"
#include "integrators/mlt/mlt_shards.h"
#include "mcmc/bootstrap.h"
#include "mcmc/chain_render.h"
#include "mcmc/chain_runner.h"
#include "mcmc/startup_parameters.h"
#include "path/path.h"
#include "progress_reporter.h"
#include "render_scene.h"
#include "sample_waves.h"
#include "share_range.h"
#include "thread_pool.h"

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
        double sum = 0;
        uint64_t rays = 0;
    };
    auto run = [&](uint64_t k, Block& block) {
        uint64_t first = k * kBootstrapBlock, end = std::min(samples, first + kBootstrapBlock);
        for (uint64_t i = first; i < end; ++i) {
            if ((i & 15) == 0) ctx.throwIfCancelled();
            block.sum += sampler.sample(i, block.candidates, block.rays);
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

ChainPlan planMltChains(const RenderContext& ctx, const BootstrapSampler& sampler,
                        const BootstrapResult& bootstrap, int chains, uint64_t mutations,
                        const PathRestriction& restriction) {
    ChainPlan plan;
    plan.seed = ctx.settings.seed;
    plan.bootstrapSamples = bootstrap.samples;
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
        plan.groups.push_back(
            {"indirect", bootstrap.samples > 0 ? sum / double(bootstrap.samples) : 0});
        starts = resampleCandidates(bootstrap.candidates, members, size_t(chains), rng);
        for (size_t& start : starts) start = members[start];
    }
    for (size_t k = 0; k < starts.size(); ++k) {
        std::vector<uint8_t> start =
            chainStart(ctx, sampler, bootstrap.candidates, starts[k], restriction);
        if (start.empty()) continue;
        PlannedChain chain;
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
    out.bootstrap = runBootstrap(ctx, sampler, settings.bootstrapSamples,
                                 startupDeadline(rs, start, settings.startupShare));
    out.bootstrapSeconds = secondsSince(start);
    ctx.throwIfCancelled();

    uint64_t byBudget = std::max<uint64_t>(1, mutations / settings.minMutationsPerChain);
    int chains = int(std::min<uint64_t>(uint64_t(std::max(1, settings.chains)), byBudget));
    out.directApart = settings.direct != "chains";
    out.plan = planMltChains(ctx, sampler, out.bootstrap, chains, mutations,
                             out.directApart ? indirectLightOnly() : PathRestriction{});
    if (out.directApart) {
        out.directSpp = settings.directSpp;
        out.bDirect = out.bootstrap.b - out.plan.groups[0].b;
    }
    return out;
}

MutationSet makeMltMutations(const RenderContext& ctx, const MltSettings& settings) {
    return makeVeachMutations(ctx.scene, ctx.camera, ctx.settings.maxDepth, settings.mutations);
}

DirectLightRun runDirectLight(const RenderContext& ctx, const MltStart& start,
                              const MltSettings& settings, double startupSeconds) {
    DirectLightRun out;
    const RenderSettings& rs = ctx.settings;
    if (!start.directApart || start.directSpp == 0) return out;
    auto begin = Clock::now();
    out.renderer = std::make_unique<DirectLightRenderer>(ctx);
    const double pixels = double(rs.width) * rs.height;
    const bool timed = rs.budgetKind == BudgetKind::Seconds;
    // A time budget's direct light stops once it has had directShare of the time the bootstrap
    // left (at least one sample per pixel: the chains never see direct paths); then a pass is
    // one sample per pixel. A mutation budget renders all its samples, in passes of at most
    // about 2^20 pixel samples (progress, cancellation; the film does not depend on them).
    const double limit =
        timed ? std::max(0.0, rs.budget - startupSeconds) * settings.directShare : 0;
    const uint64_t pass =
        timed ? 1 : std::max<uint64_t>(1, uint64_t(double(1 << 20) / std::max(1.0, pixels)));
    ProgressReporter progress(ctx.observer, "render", "samples",
                              timed ? 0 : pixels * double(start.directSpp));
    while (out.spp < start.directSpp) {
        ctx.throwIfCancelled();
        const uint64_t end = std::min(start.directSpp, out.spp + pass);
        out.renderer->renderPass({out.spp, end}, &progress);
        out.spp = end;
        if (timed && secondsSince(begin) >= limit) break;
    }
    progress.flush();
    out.seconds = secondsSince(begin);
    out.image = resolveDirectLight(out.renderer->film(), out.spp, rs.maxTypeLayers, &ctx.pool);
    return out;
}

void addDirectLightStats(RenderStats& st, bool apart, uint64_t spp, double bDirect,
                         double directRays, double chainRays) {
    st.labels["direct"] = apart ? "per-pixel" : "chains";
    st.values["direct_spp"] = double(spp);
    if (!apart) return;
    st.values["b_direct"] = bDirect;
    st.values["direct_rays"] = directRays;
    // The share of the rays after the bootstrap that went to the per-pixel direct light.
    st.values["direct_share"] =
        directRays + chainRays > 0 ? directRays / (directRays + chainRays) : 0;
}

RenderResult MltAlgorithm::render(const RenderContext& ctx) {
    const RenderSettings& rs = ctx.settings;
    auto start = Clock::now();
    double pixels = double(rs.width) * rs.height;
    MltStart mltStart = startMlt(ctx, settings_);
    const BootstrapResult& bootstrap = mltStart.bootstrap;
    const ChainPlan& plan = mltStart.plan;
    const double bootstrapSeconds = mltStart.bootstrapSeconds;
    // The direct light first (per pixel, when apart), then the chains with the time left.
    const DirectLightRun direct = runDirectLight(ctx, mltStart, settings_, bootstrapSeconds);
    const double startupSeconds = bootstrapSeconds + direct.seconds;
    auto makeMutations = [&](uint32_t) { return makeMltMutations(ctx, settings_); };
    ChainRunner::RestrictionFactory restrictions;
    if (mltStart.directApart) restrictions = [](uint32_t) { return indirectLightOnly(); };
    ChainRunner runner(ctx, plan, makeMutations, restrictions, settings_.roundMutations);
    auto resolve = [&](ThreadPool* pool) {
        LayeredImage chains = runner.resolveGroup(0, pool);
        return mltStart.directApart ? addDisjointParts(direct.image, chains, rs.maxTypeLayers)
                                    : chains;
    };
    runChainsWithPreviews(ctx, runner, plan, startupSeconds, resolve, {});

    RenderResult result;
    result.image = resolve(nullptr);
    RenderStats& st = result.stats;
    st.values["b"] = plan.groups[0].b;
    st.values["bootstrap_samples"] = double(bootstrap.samples);
    st.values["bootstrap_seconds"] = bootstrapSeconds;
    const double directRays = direct.renderer ? double(direct.renderer->rays()) : 0;
    st.values["path_types"] = double(runner.film(0).typeCount() +
                                     (direct.renderer ? direct.renderer->film().typeCount() : 0));
    addChainStats(st, runner, plan, secondsSince(start), startupSeconds,
                  bootstrap.rays + uint64_t(directRays), pixels);
    addDirectLightStats(st, mltStart.directApart, direct.spp, mltStart.bDirect, directRays,
                        double(runner.rays()));
    if (mltStart.directApart) st.values["direct_seconds"] = direct.seconds;
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
