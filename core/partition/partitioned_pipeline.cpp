#include "partition/partitioned_pipeline.h"

#include <algorithm>
#include <stdexcept>

#include "camera.h"
#include "clock.h"
#include "mcmc/bootstrap.h"
#include "mcmc/chain_render.h"
#include "mcmc/startup_parameters.h"
#include "mcmc/startup_rule.h"
#include "path_type_bytes.h"
#include "progress_reporter.h"
#include "render_scene.h"
#include "shard/chain_shards.h"
#include "thread_pool.h"

namespace partita {

namespace {

constexpr uint64_t kResampleStream = 0x50525350ull;        // "PRSP"
constexpr uint64_t kChainStreams = 0x5041525443ull << 24;  // "PARTC"

/// The indices of half B's candidates that belong to partition p (4 bytes a record instead of a
/// copy of its 40: the complement's may hold most of the pre-pass's records).
std::vector<uint32_t> candidatesOf(const PrepassResult& prepass, const Partition& p) {
    std::vector<uint32_t> out;
    for (size_t i = 0; i < prepass.candidatesB.size(); ++i)
        if (p.holds(prepass.candidatesB[i].type)) out.push_back(uint32_t(i));
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
    plan.layers = TypeLayers::of({});  // partition images are combined ones: no type layers
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
        std::vector<uint32_t> members = candidatesOf(prepass, partitions[g]);
        Rng rng(ctx.settings.seed, kResampleStream + g);
        std::vector<size_t> starts =
            resampleCandidates(prepass.candidatesB, members, size_t(chains), rng);
        const Partition& partition = partitions[g];
        for (size_t k = 0; k < starts.size(); ++k) {
            // From the drawn record on, the partition's records in the same order as a copy of
            // them would hold (the others fail `accept`).
            std::vector<uint8_t> start =
                chainStart(ctx, sampler, prepass.candidatesB, members[starts[k]],
                           [&](const PathType& t) { return partition.holds(t); });
            if (start.empty()) continue;
            PlannedChain chain;
            chain.group = uint32_t(g);
            chain.stream = stream++;
            chain.mutations = shareRange(mutations[g], starts.size(), k).count();
            chain.burnIn = StartupRule::burnIn(s.burnIn, chain.mutations, ctx.settings);
            chain.start = std::move(start);
            plan.chains.push_back(std::move(chain));
        }
    }
    return plan;
}

/// The combined image (Eq. 9: the sum of the partitions' images) and one layer per partition;
/// `imageOf(g)` is partition g's combined image (its type layers are not kept: each would be a
/// full image, K + 1 times over).
LayeredImage resolvePartitions(const std::function<Image(uint32_t)>& imageOf,
                               const std::vector<Partition>& partitions, int width, int height) {
    LayeredImage out;
    out.combined = Image(width, height);
    for (size_t g = 0; g < partitions.size(); ++g) {
        Image image = imageOf(uint32_t(g));
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

/// Partition g's mutations done and acceptance, from a runner or from merged shards.
struct GroupProgress {
    std::function<double(size_t)> mutations, acceptance, stuckChains;
};

GroupProgress progressOf(const ChainRunner& runner) {
    return {[&runner](size_t g) { return double(runner.mutationsDone(int(g))); },
            [&runner](size_t g) { return acceptanceOf(runner, g); },
            [&runner](size_t g) { return double(runner.stuckChains(int(g))); }};
}

void addPartitionStats(RenderStats& st, const std::vector<Partition>& partitions,
                       const GroupProgress& groups) {
    st.values["partitions"] = double(partitions.size());
    for (size_t g = 0; g < partitions.size(); ++g) {
        const Partition& p = partitions[g];
        std::string key = "partition_" + std::to_string(g) + "_";
        st.labels[key + "type"] = p.label;
        st.values[key + "gamma"] = p.gamma;
        st.values[key + "p"] = p.p;
        st.values[key + "b"] = p.b;
        if (!p.complement) st.values[key + "b_error"] = p.bError;
        st.values[key + "mutations"] = groups.mutations(g);
        st.values[key + "acceptance"] = groups.acceptance(g);
        st.values[key + "stuck_chains"] = groups.stuckChains(g);
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

/// Everything fixed before the chains run: the partitions, the chain plan, prepare's bytes,
/// the start-up's statistics, time and rays. (The pre-pass's records are not kept: nothing
/// after the plan reads them.)
struct PartitionedStart {
    std::vector<Partition> partitions;
    ChainPlan plan;
    std::vector<uint8_t> prepared;
    RenderStats stats;
    double startupSeconds = 0;
    uint64_t startupRays = 0;
};

PartitionedStart startPartitioned(const RenderContext& ctx,
                                  const PartitionPipelineSettings& settings,
                                  const std::string& algorithm, PartitionMutations& mutations) {
    const RenderSettings& rs = ctx.settings;
    if (!ctx.camera.isConnectable())
        throw std::invalid_argument(
            algorithm + " needs a perspective camera (its mutations connect paths to the pinhole)");
    auto start = Clock::now();
    bool timed = rs.budgetKind == BudgetKind::Seconds;
    double pixels = double(rs.width) * rs.height;

    std::string why;
    StartupEstimator estimator = choosePrepassEstimator(ctx.scene, settings.prepass, why);
    BootstrapSampler sampler(ctx.scene, ctx.camera, rs.maxDepth, rs.seed, estimator);
    uint64_t samples = StartupRule::bootstrapSamples(settings.bootstrapSamples, rs);
    PrepassResult prepass = runPrepass(ctx, sampler, samples, settings.prepassMemoryBytes,
                                       startupDeadline(rs, start, settings.startupShare));
    double prepassSeconds = secondsSince(start);
    ctx.throwIfCancelled();

    PartitionedStart out;
    out.partitions = makePartitions(prepass, settings.k);
    // A time budget has no mutation count: a nominal one only splits the chains' shares.
    uint64_t budget = timed ? (uint64_t(1) << 50) : uint64_t(rs.budget * pixels);
    std::vector<uint64_t> perPartition =
        allocateMutations(out.partitions, budget, settings.minMutationsPerChain);
    out.plan = planPartitionChains(ctx, sampler, prepass, out.partitions, perPartition, settings);
    RenderStats setupStats;
    out.prepared = mutations.prepare(ctx, prepass, out.partitions, setupStats);
    ctx.throwIfCancelled();
    // The pre-pass, the plan and the mutations' own set-up (guided's guides) come before the
    // chains: a time budget's chains get what is left.
    out.startupSeconds = secondsSince(start);
    out.startupRays = prepass.rays;

    RenderStats& st = out.stats;
    st.labels["prepass"] = why;
    st.values["prepass_samples"] = double(prepass.samplesA + prepass.samplesB);
    st.values["prepass_samples_requested"] = double(samples);
    st.values["prepass_seconds"] = prepassSeconds;
    st.values["prepass_types"] = double(prepass.gamma.size());
    st.values["prepass_candidates_truncated"] = prepass.candidatesTruncated ? 1 : 0;
    // Half B's path records, alive from the pre-pass to the end of the plan (allocated: the
    // vector's capacity).
    st.values["prepass_records"] = double(prepass.candidatesB.size());
    st.values["prepass_record_bytes"] =
        double(prepass.candidatesB.size() * sizeof(BootstrapCandidate));
    st.values["prepass_record_allocated_bytes"] =
        double(prepass.candidatesB.capacity() * sizeof(BootstrapCandidate));
    for (const auto& [key, value] : setupStats.values) st.values[key] = value;
    for (const auto& [key, label] : setupStats.labels) st.labels[key] = label;
    st.values["startup_seconds"] = out.startupSeconds;
    return out;
}

ChainRunner::RestrictionFactory restrictionsOf(const std::vector<Partition>& partitions) {
    return [&partitions](uint32_t group) -> PathRestriction {
        const Partition& p = partitions[group];
        return [p](const PathType& t) { return p.holds(t); };
    };
}

// The shard plan's state: the chain plan, the partitions, prepare's bytes, the start-up's
// statistics and rays.
void putPartition(ByteWriter& w, const Partition& p) {
    w.putString(p.label);
    w.put(uint64_t(p.types.size()));
    for (const PathType& t : p.types) putPathType(w, t);
    w.put(uint8_t(p.complement));
    w.put(p.gamma);
    w.put(p.p);
    w.put(p.b);
    w.put(p.bError);
}

Partition getPartition(ByteReader& r) {
    Partition p;
    p.label = r.getString();
    uint64_t types = r.get<uint64_t>();
    for (uint64_t i = 0; i < types; ++i) p.types.push_back(getPathType(r));
    p.complement = r.get<uint8_t>() != 0;
    p.gamma = r.get<double>();
    p.p = r.get<double>();
    p.b = r.get<double>();
    p.bError = r.get<double>();
    return p;
}

std::vector<uint8_t> serializeStart(const PartitionedStart& s) {
    ByteWriter w;
    w.putBytes(serializeChainPlan(s.plan));
    w.put(uint64_t(s.partitions.size()));
    for (const Partition& p : s.partitions) putPartition(w, p);
    w.putBytes(s.prepared);
    w.put(uint64_t(s.stats.values.size()));
    for (const auto& [key, value] : s.stats.values) {
        w.putString(key);
        w.put(value);
    }
    w.put(uint64_t(s.stats.labels.size()));
    for (const auto& [key, label] : s.stats.labels) {
        w.putString(key);
        w.putString(label);
    }
    w.put(s.startupSeconds);
    w.put(s.startupRays);
    return std::move(w.bytes);
}

PartitionedStart deserializeStart(std::span<const uint8_t> bytes) {
    ByteReader r(bytes, "partitioned plan");
    PartitionedStart s;
    s.plan = deserializeChainPlan(r.getBytes());
    uint64_t partitions = r.get<uint64_t>();
    for (uint64_t i = 0; i < partitions; ++i) s.partitions.push_back(getPartition(r));
    if (s.partitions.size() != s.plan.groups.size()) r.fail("partitions and groups differ");
    s.prepared = r.getBytes();
    uint64_t values = r.get<uint64_t>();
    for (uint64_t i = 0; i < values; ++i) {
        std::string key = r.getString();
        s.stats.values[key] = r.get<double>();
    }
    uint64_t labels = r.get<uint64_t>();
    for (uint64_t i = 0; i < labels; ++i) {
        std::string key = r.getString();
        s.stats.labels[key] = r.getString();
    }
    s.startupSeconds = r.get<double>();
    s.startupRays = r.get<uint64_t>();
    if (!r.atEnd()) r.fail("trailing bytes");
    return s;
}

}  // namespace

VeachMutationSettings partitionMutationSettings(VeachMutationSettings base,
                                                const Partition& partition) {
    if (!partition.complement) {
        base.bidirectional.additionWeights = {1.0, 0.0};
        // The independence mutation proposes only the lengths of the partition's types.
        for (const PathType& t : partition.types)
            base.independenceVertexCounts.push_back(t.scatteringVertices() + 2);
    }
    return base;
}

RenderResult renderPartitioned(const RenderContext& ctx, const PartitionPipelineSettings& settings,
                               const std::string& algorithm, PartitionMutations& mutations) {
    const RenderSettings& rs = ctx.settings;
    auto start = Clock::now();
    const PartitionedStart st = startPartitioned(ctx, settings, algorithm, mutations);
    const std::vector<Partition>& partitions = st.partitions;
    // The factory owns what the mutations read (guided's guides): it lives as long as the runner.
    const ChainRunner::MutationFactory factory = mutations.factory(ctx, partitions, st.prepared);
    ChainRunner runner(ctx, st.plan, factory, restrictionsOf(partitions), settings.roundMutations);
    auto imageOf = [&](uint32_t g) { return runner.resolveGroupCombined(g); };
    runChainsWithPreviews(
        ctx, runner, st.plan, st.startupSeconds,
        [&](ThreadPool*) { return resolvePartitions(imageOf, partitions, rs.width, rs.height); },
        [&](RenderStats& stats) { addPartitionStats(stats, partitions, progressOf(runner)); },
        [&](ProgressReporter& progress) {
            progress.setPartitions(partitionProgress(partitions, runner));
        });

    RenderResult result;
    result.image = resolvePartitions(imageOf, partitions, rs.width, rs.height);
    result.stats = st.stats;
    addChainStats(result.stats, runner, st.plan, secondsSince(start), st.startupSeconds,
                  st.startupRays, double(rs.width) * rs.height);
    addPartitionStats(result.stats, partitions, progressOf(runner));
    return result;
}

std::vector<uint8_t> PartitionedShards::plan(const RenderContext& ctx) {
    requireMutationBudget(ctx, algorithm_);
    return serializeStart(startPartitioned(ctx, settings_, algorithm_, mutations_));
}

uint32_t PartitionedShards::maxShards(const RenderContext&, std::span<const uint8_t> plan) const {
    return uint32_t(std::max<size_t>(1, deserializeStart(plan).plan.chains.size()));
}

ShardWork PartitionedShards::renderShard(const RenderContext& ctx, std::span<const uint8_t> bytes,
                                         uint32_t shard, uint32_t shards) {
    const PartitionedStart st = deserializeStart(bytes);
    // The factory owns what the mutations read (guided's guides): it lives as long as the runner.
    const ChainRunner::MutationFactory factory =
        mutations_.factory(ctx, st.partitions, st.prepared);
    return runChainShard(ctx, st.plan, shard, shards, factory, restrictionsOf(st.partitions),
                         settings_.roundMutations);
}

RenderResult PartitionedShards::resolve(const RenderContext& ctx, std::span<const uint8_t> bytes,
                                        const ShardWork& merged) {
    const PartitionedStart st = deserializeStart(bytes);
    const RenderSettings& rs = ctx.settings;
    if (merged.films.size() != st.partitions.size())
        throw std::invalid_argument("merged work has " + std::to_string(merged.films.size()) +
                                    " films for " + std::to_string(st.partitions.size()) +
                                    " partitions");
    auto imageOf = [&](uint32_t g) {
        return merged.films[g].resolveCombined(
            ChainRunner::filmScale(st.plan.groups[g].b, rs.width, rs.height, merged.counts[g]));
    };
    auto sum = [&](const std::string& key) {
        auto it = merged.sums.find(key);
        return it == merged.sums.end() ? 0.0 : it->second;
    };
    GroupProgress groups{
        [&](size_t g) { return double(merged.counts[g]); },
        [&](size_t g) {
            const std::string key = "group_" + std::to_string(g) + "_";
            double proposed = sum(key + "proposed");
            return proposed > 0 ? sum(key + "accepted") / proposed : 0.0;
        },
        [&](size_t g) { return sum("group_" + std::to_string(g) + "_stuck_chains"); }};
    RenderResult result;
    result.image = resolvePartitions(imageOf, st.partitions, rs.width, rs.height);
    result.stats = st.stats;
    addMergedChainStats(result.stats, merged, st.plan, double(rs.width) * rs.height);
    result.stats.values["rays"] += double(st.startupRays);
    addPartitionStats(result.stats, st.partitions, groups);
    return result;
}

}  // namespace partita
