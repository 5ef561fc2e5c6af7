#include "partition/partitioned_pipeline.h"

#include <algorithm>
#include <stdexcept>

#include "camera.h"
#include "clock.h"
#include "mcmc/bootstrap.h"
#include "mcmc/chain_render.h"
#include "progress_reporter.h"
#include "render_scene.h"
#include "thread_pool.h"

namespace partita {

namespace {

constexpr uint64_t kResampleStream = 0x50525350ull;        // "PRSP"
constexpr uint64_t kChainStreams = 0x5041525443ull << 24;  // "PARTC"

/// Half B's candidates that belong to partition p.
std::vector<BootstrapCandidate> candidatesOf(const PrepassResult& prepass, const Partition& p) {
    std::vector<BootstrapCandidate> out;
    for (const BootstrapCandidate& c : prepass.candidatesB)
        if (p.holds(c.type)) out.push_back(c);
    return out;
}

/// The chain plan of the partitions: group g is partition g; its chains (in proportion to its
/// mutations, at least one) start from half B's paths of the partition, resampled in
/// proportion to their contributions.
ChainPlan planPartitionChains(const RenderContext& ctx, const BootstrapSampler& sampler,
                              const PrepassResult& prepass,
                              const std::vector<Partition>& partitions,
                              const std::vector<uint64_t>& mutations,
                              const PartitionPipelineSettings& s) {
    ChainPlan plan;
    plan.seed = ctx.settings.seed;
    plan.bootstrapSamples = prepass.samplesA + prepass.samplesB;
    uint64_t total = 0;
    for (uint64_t m : mutations) total += m;
    uint64_t stream = kChainStreams;
    for (size_t g = 0; g < partitions.size(); ++g) {
        plan.groups.push_back({partitions[g].label, partitions[g].b});
        if (mutations[g] == 0) continue;
        double share = double(mutations[g]) / double(std::max<uint64_t>(1, total));
        uint64_t byShare = uint64_t(std::llround(share * double(s.chains)));
        uint64_t chains = std::clamp<uint64_t>(
            byShare, 1, std::max<uint64_t>(1, mutations[g] / s.minMutationsPerChain));
        std::vector<BootstrapCandidate> candidates = candidatesOf(prepass, partitions[g]);
        Rng rng(ctx.settings.seed, kResampleStream + g);
        std::vector<size_t> starts = resampleCandidates(candidates, size_t(chains), rng);
        const Partition& partition = partitions[g];
        for (size_t k = 0; k < starts.size(); ++k) {
            std::vector<uint8_t> start =
                chainStart(ctx, sampler, candidates, starts[k],
                           [&](const PathType& t) { return partition.holds(t); });
            if (start.empty()) continue;
            PlannedChain chain;
            chain.group = uint32_t(g);
            chain.stream = stream++;
            chain.mutations = chainShare(mutations[g], starts.size(), k);
            chain.burnIn = s.burnIn;
            chain.start = std::move(start);
            plan.chains.push_back(std::move(chain));
        }
    }
    return plan;
}

/// The combined image (Eq. 9: the sum of the partitions' images) and one layer per partition.
LayeredImage resolvePartitions(const ChainRunner& runner, const std::vector<Partition>& partitions,
                               int width, int height) {
    LayeredImage out;
    out.combined = Image(width, height);
    for (size_t g = 0; g < partitions.size(); ++g) {
        // The combined image only: a partition's type layers are not kept (each would be a
        // full image, K + 1 times over).
        Image image = runner.resolveGroupCombined(uint32_t(g));
        if (image.empty()) image = Image(width, height);
        for (size_t i = 0; i < image.rgb.size(); ++i) out.combined.rgb[i] += image.rgb[i];
        out.layers.push_back({partitions[g].label, std::move(image)});
    }
    return out;
}

/// Accepted over proposed over all the mutations of partition g's chains so far (0 before any).
double acceptanceOf(const ChainRunner& runner, size_t g) {
    uint64_t proposed = 0, accepted = 0;
    for (const auto& [name, m] : runner.mutationStats(int(g))) {
        proposed += m.proposed;
        accepted += m.accepted;
    }
    return proposed ? double(accepted) / double(proposed) : 0;
}

void addPartitionStats(RenderStats& st, const std::vector<Partition>& partitions,
                       const ChainRunner& runner) {
    st.values["partitions"] = double(partitions.size());
    for (size_t g = 0; g < partitions.size(); ++g) {
        const Partition& p = partitions[g];
        std::string key = "partition_" + std::to_string(g) + "_";
        st.labels[key + "type"] = p.label;
        st.values[key + "gamma"] = p.gamma;
        st.values[key + "p"] = p.p;
        st.values[key + "b"] = p.b;
        if (!p.complement) st.values[key + "b_error"] = p.bError;
        st.values[key + "mutations"] = double(runner.mutationsDone(int(g)));
        st.values[key + "acceptance"] = acceptanceOf(runner, g);
    }
}

/// Per partition: its type string, P(i), b_i, gamma and the running acceptance of its chains
/// (accepted / proposed over all its mutations so far).
std::vector<PartitionProgress> partitionProgress(const std::vector<Partition>& partitions,
                                                 const ChainRunner& runner) {
    std::vector<PartitionProgress> out;
    for (size_t g = 0; g < partitions.size(); ++g) {
        PartitionProgress pp;
        pp.type = partitions[g].label;
        pp.p = partitions[g].p;
        pp.b = partitions[g].b;
        pp.gamma = partitions[g].gamma;
        pp.acceptance = acceptanceOf(runner, g);
        out.push_back(std::move(pp));
    }
    return out;
}

}  // namespace

VeachMutationSettings partitionMutationSettings(VeachMutationSettings base,
                                                const Partition& partition) {
    if (!partition.complement) base.bidirectional.additionWeights = {1.0, 0.0};
    return base;
}

RenderResult renderPartitioned(const RenderContext& ctx, const PartitionPipelineSettings& settings,
                               const std::string& algorithm,
                               const PartitionMutationHook& mutationHook) {
    const RenderSettings& rs = ctx.settings;
    if (!ctx.camera.isConnectable())
        throw std::invalid_argument(
            algorithm + " needs a perspective camera (its mutations connect paths to the pinhole)");
    auto start = Clock::now();
    bool timed = rs.budgetKind == BudgetKind::Seconds;
    double pixels = double(rs.width) * rs.height;

    std::string why;
    StartupEstimator estimator = choosePrepassEstimator(ctx.scene, rs.prepass, why);
    BootstrapSampler sampler(ctx.scene, ctx.camera, rs.maxDepth, rs.seed, estimator);
    uint64_t samples = rs.bootstrapSamples > 0 ? rs.bootstrapSamples : settings.prepassSamples;
    PrepassResult prepass = runPrepass(ctx, sampler, samples, settings.prepassMemoryBytes);
    double prepassSeconds = secondsSince(start);
    ctx.throwIfCancelled();

    std::vector<Partition> partitions = makePartitions(prepass, rs.partitions);
    // A time budget has no mutation count: a nominal one only splits the chains' shares.
    uint64_t budget = timed ? (uint64_t(1) << 50) : uint64_t(rs.budget * pixels);
    std::vector<uint64_t> mutations =
        allocateMutations(partitions, budget, settings.minMutationsPerChain);
    ChainPlan plan = planPartitionChains(ctx, sampler, prepass, partitions, mutations, settings);
    RenderStats setupStats;
    ChainRunner::MutationFactory makeMutations = mutationHook(prepass, partitions, setupStats);
    ctx.throwIfCancelled();
    // The pre-pass, the plan and the hook's own set-up (guided's guides) come before the chains:
    // a time budget's chains get what is left.
    double startupSeconds = secondsSince(start);
    auto restriction = [&](uint32_t group) -> PathRestriction {
        const Partition& p = partitions[group];
        return [p](const PathType& t) { return p.holds(t); };
    };
    ChainRunner runner(ctx, plan, makeMutations, restriction, settings.roundMutations);
    runChainsWithPreviews(
        ctx, runner, plan, startupSeconds,
        [&](ThreadPool*) { return resolvePartitions(runner, partitions, rs.width, rs.height); },
        [&](RenderStats& st) { addPartitionStats(st, partitions, runner); },
        [&](ProgressReporter& progress) {
            progress.setPartitions(partitionProgress(partitions, runner));
        });

    RenderResult result;
    result.image = resolvePartitions(runner, partitions, rs.width, rs.height);
    RenderStats& st = result.stats;
    st.labels["prepass"] = why;
    st.values["prepass_samples"] = double(samples);
    st.values["prepass_seconds"] = prepassSeconds;
    st.values["prepass_types"] = double(prepass.gamma.size());
    st.values["prepass_candidates_truncated"] = prepass.candidatesTruncated ? 1 : 0;
    // Half B's path records, alive from the pre-pass to the end of the render (allocated: the
    // vector's capacity).
    st.values["prepass_records"] = double(prepass.candidatesB.size());
    st.values["prepass_record_bytes"] =
        double(prepass.candidatesB.size() * sizeof(BootstrapCandidate));
    st.values["prepass_record_allocated_bytes"] =
        double(prepass.candidatesB.capacity() * sizeof(BootstrapCandidate));
    st.values["burn_in"] = double(settings.burnIn);
    for (const auto& [key, value] : setupStats.values) st.values[key] = value;
    for (const auto& [key, label] : setupStats.labels) st.labels[key] = label;
    st.values["startup_seconds"] = startupSeconds;
    addChainStats(st, runner, plan, secondsSince(start), startupSeconds, prepass.rays, pixels);
    addPartitionStats(st, partitions, runner);
    return result;
}

}  // namespace partita
