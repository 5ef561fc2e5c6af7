#include "integrators/mlt/mlt_integrator.h"

#include <algorithm>
#include <map>
#include <stdexcept>

#include "camera.h"
#include "clock.h"
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

TypeLayers bootstrapTypeLayers(const RenderSettings& settings,
                               const std::vector<BootstrapCandidate>& candidates) {
    std::map<PathType, double> weights;
    if (needsTypeWeights(settings))
        for (const BootstrapCandidate& c : candidates) weights[c.type] += double(c.weight);
    return chooseTypeLayers(settings, weights);
}

ChainPlan planMltChains(const RenderContext& ctx, const BootstrapSampler& sampler,
                        const BootstrapResult& bootstrap, int chains, uint64_t mutations) {
    ChainPlan plan;
    plan.seed = ctx.settings.seed;
    plan.bootstrapSamples = bootstrap.samples;
    plan.groups.push_back({"all", bootstrap.b});
    plan.layers = bootstrapTypeLayers(ctx.settings, bootstrap.candidates);
    Rng rng(ctx.settings.seed, kResampleStream);
    std::vector<size_t> starts = resampleCandidates(bootstrap.candidates, size_t(chains), rng);
    for (size_t k = 0; k < starts.size(); ++k) {
        std::vector<uint8_t> start = chainStart(ctx, sampler, bootstrap.candidates, starts[k]);
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
    out.plan = planMltChains(ctx, sampler, out.bootstrap, chains, mutations);
    return out;
}

MutationSet makeMltMutations(const RenderContext& ctx, const MltSettings& settings) {
    return makeVeachMutations(ctx.scene, ctx.camera, ctx.settings.maxDepth, settings.mutations);
}

RenderResult MltAlgorithm::render(const RenderContext& ctx) {
    const RenderSettings& rs = ctx.settings;
    auto start = Clock::now();
    double pixels = double(rs.width) * rs.height;
    MltStart mltStart = startMlt(ctx, settings_);
    const BootstrapResult& bootstrap = mltStart.bootstrap;
    const ChainPlan& plan = mltStart.plan;
    const double bootstrapSeconds = mltStart.bootstrapSeconds;
    auto makeMutations = [&](uint32_t) { return makeMltMutations(ctx, settings_); };
    ChainRunner runner(ctx, plan, makeMutations, {}, settings_.roundMutations);
    runChainsWithPreviews(ctx, runner, plan, bootstrapSeconds,
                          [&](ThreadPool* pool) { return runner.resolveGroup(0, pool); }, {});

    RenderResult result;
    RenderStats& st = result.stats;
    st.values["b"] = bootstrap.b;
    st.values["bootstrap_samples"] = double(bootstrap.samples);
    st.values["bootstrap_seconds"] = bootstrapSeconds;
    st.values["path_types"] = double(runner.film(0).typeCount());
    result.image = runner.takeResolvedGroup(0, &ctx.pool);
    addChainStats(st, runner, plan, secondsSince(start), bootstrapSeconds, bootstrap.rays, pixels);
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
