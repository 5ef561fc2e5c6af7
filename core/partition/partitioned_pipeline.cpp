#include "partition/partitioned_pipeline.h"

#include <algorithm>
#include <stdexcept>

#include "camera.h"
#include "clock.h"
#include "half_split_error.h"
#include "mcmc/bootstrap.h"
#include "mcmc/chain_error_monitor.h"
#include "mcmc/chain_render.h"
#include "mcmc/startup_parameters.h"
#include "mcmc/startup_rule.h"
#include "partition/effort_pilot.h"
#include "partition/partition_chains.h"
#include "partition/partition_error.h"
#include "partition/per_pixel_partitions.h"
#include "path_type_bytes.h"
#include "preview_schedule.h"
#include "progress_reporter.h"
#include "render_scene.h"
#include "shard/chain_shards.h"
#include "thread_pool.h"

namespace partita {

namespace {

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
        st.labels[key + "estimator"] = p.perPixel ? "per-pixel" : "chains";
        st.values[key + "gamma"] = p.gamma;
        st.values[key + "p"] = p.p;
        st.values[key + "b"] = p.b;
        st.values[key + "b_error"] = p.bError;
        st.values[key + "mutations"] = groups.mutations(g);
        st.values[key + "acceptance"] = groups.acceptance(g);
        st.values[key + "stuck_chains"] = groups.stuckChains(g);
    }
}

/// Per partition: its type string, P(i), b_i, gamma, the running acceptance of its chains
/// (accepted / proposed over all its mutations so far; 0 without a runner: the per-pixel
/// samples come before the chains), its estimator and, with more than one of `moves` to
/// choose from, its chains' move.
std::vector<PartitionProgress> partitionProgress(const std::vector<Partition>& partitions,
                                                 const ChainRunner* runner,
                                                 const std::vector<std::string>& moves) {
    std::vector<PartitionProgress> out;
    for (size_t g = 0; g < partitions.size(); ++g) {
        PartitionProgress pp;
        pp.type = partitions[g].label;
        pp.p = partitions[g].p;
        pp.b = partitions[g].b;
        pp.gamma = partitions[g].gamma;
        pp.acceptance = runner ? acceptanceOf(*runner, g) : 0;
        pp.estimator = partitions[g].perPixel ? "per-pixel" : "chains";
        // The move, where there was one to choose.
        if (!partitions[g].perPixel && moves.size() > 1 && partitions[g].move < moves.size())
            pp.move = moves[partitions[g].move];
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
    uint64_t perPixelSpp = 0;  // a mutation budget's per-pixel samples of every pixel
    double pixelShare = 0;     // a time budget's share of the time left for them
    PerPixelEstimator pixelEstimator = PerPixelEstimator::Bdpt;
    /// The chosen per-pixel estimator's pilot variances (PerPixelPilot::varianceRgb), for the
    /// error estimate; not in a shard plan (a sharded job estimates none).
    std::vector<double> pixelVarianceRgb;
    /// The chosen per-pixel pilot's V_g summed over the per-pixel partitions and the samples
    /// per pixel it took (2k): a time budget's per-pixel phase pools it with its own samples
    /// (renderPerPixel). Not in a shard plan.
    double pixelPilotVariance = 0;
    double pixelPilotSamples = 0;

    bool anyPerPixel() const {
        for (const Partition& p : partitions)
            if (p.perPixel) return true;
        return false;
    }
};

ChainRunner::RestrictionFactory restrictionsOf(const std::vector<Partition>& partitions) {
    return [&partitions](uint32_t group) -> PathRestriction {
        const Partition& p = partitions[group];
        return [p](const PathType& t) { return p.holds(t); };
    };
}

/// The pilots' measurements and the effort plan into the start's statistics.
void addEffortStats(RenderStats& st, const EffortMeasurement& m, const EffortPlan& plan,
                    double pixelCost, const std::vector<std::string>& moves) {
    st.values["pilot_seconds"] = m.seconds;
    st.values["pilot_rays"] = double(m.rays);
    st.values["pilot_mutations"] = double(m.chainMutations);
    st.values["pixel_cost"] = pixelCost;
    for (const PixelPilot& pilot : m.pixelPilots) {
        const std::string name = perPixelEstimatorName(pilot.estimator);
        st.values["pixel_cost_" + name] = pilot.cost;
        double variance = 0;
        for (size_t g = 0; g < pilot.variance.size(); ++g) {
            variance += pilot.variance[g];
            st.values["partition_" + std::to_string(g) + "_pixel_variance_" + name] =
                pilot.variance[g];
        }
        st.values["pixel_variance_" + name] = variance;
    }
    st.values["per_pixel_share"] = plan.pixelShare;
    st.values["predicted_error_x_cost"] = plan.errorTimesCost;
    for (size_t g = 0; g < m.partitions.size(); ++g) {
        const std::string key = "partition_" + std::to_string(g) + "_";
        st.values[key + "chain_variance"] = m.partitions[g].chainVariance;
        st.values[key + "mutation_cost"] = m.partitions[g].mutationCost;
        st.values[key + "pixel_variance"] = m.partitions[g].pixelVariance;
        st.values[key + "share"] = plan.perPixel[g] ? 0.0 : plan.chainShare[g];
        st.labels[key + "reason"] = plan.reason[g];
        // With moves to choose from: each one's pilot and the choice (a partition the plan
        // then gives per-pixel samples keeps it, unused; the direct light has no chains' pilot).
        if (moves.size() < 2 || g >= m.move.size() || m.partitions[g].alwaysPerPixel) continue;
        st.labels[key + "move"] = moves[m.move[g]];
        for (size_t k = 0; k < moves.size() && k < m.movePilots.size(); ++k) {
            st.values[key + "chain_variance_" + moves[k]] = m.movePilots[k].variance[g];
            st.values[key + "mutation_cost_" + moves[k]] = m.movePilots[k].cost[g];
        }
    }
}

/// Each partition's estimator and its mutations (issue #23 1, 3; effort_plan.h): the pilots,
/// then the plan. The paper's Eq. 10 ("p") runs no pilot. A mutation budget is a cost: its
/// mutations at the pilot's mean cost per mutation, shared by the plan; a per-pixel-only render
/// reads it as samples per pixel.
std::vector<uint64_t> chooseEffort(const RenderContext& ctx, const BootstrapSampler& sampler,
                                   const PrepassResult& prepass,
                                   const PartitionPipelineSettings& settings,
                                   PartitionMutations& mutations, Clock::time_point start,
                                   PartitionedStart& out) {
    const RenderSettings& rs = ctx.settings;
    const bool timed = rs.budgetKind == BudgetKind::Seconds;
    // A time budget has no mutation count: a nominal one only splits the chains' shares.
    const uint64_t budget =
        timed ? (uint64_t(1) << 50) : uint64_t(rs.budget * double(rs.width) * double(rs.height));
    const EstimatorChoice choice = parseEstimatorChoice(settings.estimators);
    // Eq. 10 is the paper's allocation of chains' mutations: with per-pixel estimators the
    // budget is split by the rule.
    const bool neyman = settings.allocation != "p" || choice != EstimatorChoice::Chains;
    out.stats.labels["estimators"] = settings.estimators;
    out.stats.labels["allocation"] = neyman ? "neyman" : "p";
    std::vector<Partition>& partitions = out.partitions;
    if (partitions.empty() || !neyman)
        return allocateMutations(partitions, budget, settings.minMutationsPerChain);

    // One mutation factory per move to choose from, each with that move for every partition.
    const std::vector<std::string> moveNames = mutations.moves();
    std::vector<ChainRunner::MutationFactory> moves;
    for (size_t k = 0; k < std::max<size_t>(1, moveNames.size()); ++k) {
        std::vector<Partition> withMove = partitions;
        for (Partition& p : withMove) p.move = uint8_t(k);
        moves.push_back(mutations.factory(ctx, withMove, out.prepared));
    }
    EffortMeasurement m =
        measureEffort(ctx, sampler, prepass, partitions, moves, restrictionsOf(partitions),
                      settings, choice, timed ? rs.budget - secondsSince(start) : 0);
    for (size_t g = 0; g < partitions.size() && g < m.move.size(); ++g)
        partitions[g].move = m.move[g];
    // The plan with each per-pixel estimator piloted, the one of lower error x cost (none
    // piloted: chains only).
    EffortPlan plan = planEffort(m.partitions, 0, choice, true);
    double pixelCost = 0;
    const PixelPilot* chosenPilot = nullptr;
    for (size_t i = 0; i < m.pixelPilots.size(); ++i) {
        const PixelPilot& pilot = m.pixelPilots[i];
        std::vector<PartitionEffort> with = m.partitions;
        for (size_t g = 0; g < with.size(); ++g) with[g].pixelVariance = pilot.variance[g];
        EffortPlan candidate = planEffort(with, pilot.cost, choice, true);
        if (i == 0 || candidate.errorTimesCost < plan.errorTimesCost) {
            plan = std::move(candidate);
            pixelCost = pilot.cost;
            out.pixelEstimator = pilot.estimator;
            out.pixelVarianceRgb = pilot.varianceRgb;
            chosenPilot = &pilot;
        }
    }
    addEffortStats(out.stats, m, plan, pixelCost, moveNames);
    out.stats.labels["per_pixel_estimator"] = perPixelEstimatorName(out.pixelEstimator);
    out.startupRays += m.rays;
    bool anyPixel = false;
    for (size_t g = 0; g < partitions.size(); ++g) {
        partitions[g].perPixel = plan.perPixel[g];
        anyPixel = anyPixel || plan.perPixel[g];
        if (plan.perPixel[g] && chosenPilot && g < chosenPilot->variance.size())
            out.pixelPilotVariance += chosenPilot->variance[g];
    }
    if (chosenPilot) out.pixelPilotSamples = chosenPilot->samplesPerPixel;
    std::vector<uint64_t> perPartition(partitions.size(), 0);
    if (timed) {
        // Chains per partition in proportion to its mutation rate, share_g / c_g.
        double sum = 0;
        for (size_t g = 0; g < partitions.size(); ++g)
            if (!plan.perPixel[g] && m.partitions[g].mutationCost > 0)
                sum += plan.chainShare[g] / m.partitions[g].mutationCost;
        for (size_t g = 0; g < partitions.size(); ++g) {
            if (plan.perPixel[g]) continue;
            const double rate = m.partitions[g].mutationCost > 0
                                    ? plan.chainShare[g] / m.partitions[g].mutationCost
                                    : 0;
            perPartition[g] = std::max<uint64_t>(
                settings.minMutationsPerChain,
                uint64_t(sum > 0 ? rate / sum * double(budget) : double(budget)));
        }
        out.pixelShare = anyPixel ? plan.pixelShare : 0;
        return perPartition;
    }
    const double cost = double(budget) * m.mutationCost;  // rays
    for (size_t g = 0; g < partitions.size(); ++g) {
        if (plan.perPixel[g]) continue;
        const double c = m.partitions[g].mutationCost;
        perPartition[g] = std::max<uint64_t>(
            settings.minMutationsPerChain,
            c > 0 ? uint64_t(std::llround(plan.chainShare[g] * cost / c)) : budget);
    }
    if (anyPixel) {
        const double spp =
            cost > 0 && pixelCost > 0 ? std::ceil(plan.pixelShare * cost / pixelCost) : rs.budget;
        out.perPixelSpp = uint64_t(std::clamp(spp, 1.0, double(uint64_t(1) << 20)));
    }
    return perPartition;
}

PartitionedStart startPartitioned(const RenderContext& ctx,
                                  const PartitionPipelineSettings& settings,
                                  const std::string& algorithm, PartitionMutations& mutations) {
    const RenderSettings& rs = ctx.settings;
    if (!ctx.camera.isConnectable())
        throw std::invalid_argument(
            algorithm + " needs a perspective camera (its mutations connect paths to the pinhole)");
    auto start = Clock::now();

    std::string why;
    StartupEstimator estimator = choosePrepassEstimator(ctx.scene, settings.prepass, why);
    BootstrapSampler sampler(ctx.scene, ctx.camera, rs.maxDepth, rs.seed, estimator);
    uint64_t samples = StartupRule::bootstrapSamples(settings.bootstrapSamples, rs);
    PrepassResult prepass = runPrepass(ctx, sampler, samples, settings.prepassMemoryBytes,
                                       startupDeadline(rs, start, settings.startupShare));
    double prepassSeconds = secondsSince(start);
    ctx.throwIfCancelled();

    PartitionedStart out;
    // The direct light apart when the estimators are chosen (pipeline_settings.h, "direct").
    const bool directApart = settings.direct == "per-pixel" &&
                             parseEstimatorChoice(settings.estimators) != EstimatorChoice::Chains;
    out.partitions = makePartitions(prepass, settings.k, kMaxBRelativeError,
                                    parsePartitionShape(settings.partitions), directApart);
    RenderStats setupStats;
    out.prepared = mutations.prepare(ctx, prepass, out.partitions, setupStats);
    ctx.throwIfCancelled();
    out.startupRays = prepass.rays;
    const std::vector<uint64_t> perPartition =
        chooseEffort(ctx, sampler, prepass, settings, mutations, start, out);
    ctx.throwIfCancelled();
    out.plan = planPartitionChains(ctx, sampler, prepass, out.partitions, perPartition, settings);
    // The pre-pass, the mutations' own set-up (guided's guides), the pilots and the plan come
    // before the chains: a time budget's chains get what is left.
    out.startupSeconds = secondsSince(start);

    RenderStats& st = out.stats;
    st.labels["prepass"] = why;
    st.values["prepass_samples"] = double(prepass.samplesA + prepass.samplesB);
    st.values["prepass_samples_requested"] = double(samples);
    st.values["prepass_seconds"] = prepassSeconds;
    st.values["prepass_types"] = double(prepass.gamma.size());
    st.labels["partitions_shape"] = settings.partitions;
    st.values["complement_b_share"] = complementShareOfB(out.partitions);
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

// The shard plan's state: the chain plan, the partitions, prepare's bytes, the start-up's
// statistics and rays.
void putPartition(ByteWriter& w, const Partition& p) {
    w.putString(p.label);
    w.put(uint64_t(p.patterns.size()));
    for (const TypePattern& t : p.patterns) w.putString(t.toString());
    w.put(uint8_t(p.complement));
    w.put(p.gamma);
    w.put(p.p);
    w.put(p.b);
    w.put(p.bError);
    w.put(uint8_t(p.perPixel));
    w.put(uint8_t(p.direct));
    w.put(uint8_t(p.directApart));
    w.put(p.move);
}

Partition getPartition(ByteReader& r) {
    Partition p;
    p.label = r.getString();
    const uint64_t patterns = r.get<uint64_t>();
    for (uint64_t i = 0; i < patterns; ++i) {
        TypePattern t;
        if (!TypePattern::parse(r.getString(), t)) r.fail("a partition's pattern is malformed");
        p.patterns.push_back(t);
    }
    p.complement = r.get<uint8_t>() != 0;
    p.gamma = r.get<double>();
    p.p = r.get<double>();
    p.b = r.get<double>();
    p.bError = r.get<double>();
    p.perPixel = r.get<uint8_t>() != 0;
    p.direct = r.get<uint8_t>() != 0;
    p.directApart = r.get<uint8_t>() != 0;
    p.move = r.get<uint8_t>();
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
    w.put(s.perPixelSpp);
    w.put(s.pixelShare);
    w.put(uint8_t(s.pixelEstimator));
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
    s.perPixelSpp = r.get<uint64_t>();
    s.pixelShare = r.get<double>();
    const uint8_t estimator = r.get<uint8_t>();
    if (estimator > uint8_t(PerPixelEstimator::PathTracer)) r.fail("unknown per-pixel estimator");
    s.pixelEstimator = PerPixelEstimator(estimator);
    if (!r.atEnd()) r.fail("trailing bytes");
    return s;
}

}  // namespace

VeachMutationSettings partitionMutationSettings(VeachMutationSettings base,
                                                const Partition& partition) {
    // One exact type: the bidirectional mutation keeps the length, the independence mutation
    // proposes only it. A class or the complement: every mutation, as mlt's.
    if (!partition.complement && partition.patterns.size() == 1 &&
        partition.patterns[0].isExact()) {
        base.bidirectional.additionWeights = {1.0, 0.0};
        base.independenceVertexCounts.push_back(
            partition.patterns[0].exactType().scatteringVertices() + 2);
    }
    return base;
}

namespace {

/// The per-pixel partitions' samples (renderPerPixel).
struct PerPixelRun {
    std::unique_ptr<PerPixelPartitions> renderer;
    uint64_t spp = 0;
    double seconds = 0;
    bool reachedTarget = false;  // stopped at the target error (no chains to follow)
    double pooledVariance = -1;  // a time budget's last re-read V (negative: none)
    double share = -1;           // and the share it gave
};

/// A preview of the per-pixel phase: its partitions' images so far, the chains' partitions
/// black (they have not started).
void previewPerPixel(const RenderContext& ctx, const PartitionedStart& st, const PerPixelRun& run,
                     std::vector<Image> images, Clock::time_point start) {
    RenderStats stats;
    stats.values["per_pixel_spp"] = double(run.spp);
    stats.values["seconds"] = secondsSince(start);
    ctx.observer.onPreview(
        resolvePartitions([&](uint32_t g) { return std::move(images[g]); }, st.partitions,
                          ctx.settings.width, ctx.settings.height),
        stats);
}

/// The samples of the per-pixel phase's next pass: one first (a preview right after it), then
/// as many as end when the next preview is due (kPassSecondsWithoutPreviews without previews,
/// a quarter of a second with a time budget, which must not be overshot), at most the samples
/// so far while a target error is watched (the estimate is looked at after each pass), never
/// past `most`.
uint64_t nextPerPixelPass(const RenderContext& ctx, const PerPixelRun& run, uint64_t most,
                          double secondsPerSample, const PreviewSchedule& previews, double timeLeft,
                          bool watch) {
    if (run.spp == 0) return 1;
    const RenderSettings& rs = ctx.settings;
    const bool timed = rs.budgetKind == BudgetKind::Seconds;
    double window = timed ? 0.25 : kPassSecondsWithoutPreviews;
    if (previews.enabled()) window = previews.untilDue();
    if (timed) window = std::min(window, timeLeft);
    uint64_t n =
        secondsPerSample > 0 ? uint64_t(std::clamp(window / secondsPerSample, 1.0, 4096.0)) : 1;
    if (watch) n = std::min(n, std::max<uint64_t>(run.spp, 2));
    return std::min(n, most - run.spp);
}

/// The per-pixel phase (none when every partition has chains): a mutation budget's planned
/// samples per pixel, or a time budget's share of the time left after the start-up (at least
/// one sample: the chains never see these partitions' paths), in passes with previews between
/// them (the images do not depend on the split). Phase "render", in samples.
PerPixelRun renderPerPixel(const RenderContext& ctx, const PartitionedStart& st,
                           const std::vector<std::string>& moves, Clock::time_point start,
                           double targetError) {
    PerPixelRun out;
    if (!st.anyPerPixel()) return out;
    const RenderSettings& rs = ctx.settings;
    const bool timed = rs.budgetKind == BudgetKind::Seconds;
    const double pixels = double(rs.width) * rs.height;
    const uint64_t most = timed ? (uint64_t(1) << 20) : st.perPixelSpp;
    const double timeLeft = std::max(0.0, rs.budget - secondsSince(start));
    double share = timed ? st.pixelShare * timeLeft : 0;
    // With a target to watch and no chains to follow, the render's own estimate stops it.
    const bool watch = targetError > 0 && st.plan.chains.empty();
    PreviewSchedule previews(ctx);
    auto begin = Clock::now();
    out.renderer = std::make_unique<PerPixelPartitions>(ctx, st.partitions, st.pixelEstimator);
    // A time budget's share is re-read from the samples so far (rereadPixelShare): two
    // resolves of the combined sums, at most a twentieth of the phase's time.
    const bool reread =
        timed && st.pixelPilotVariance > 0 && st.pixelShare > 0 && st.pixelShare < 1;
    if (reread) out.renderer->keepOddHalf();
    CostBoundedSchedule rereads(0, 20);
    ProgressReporter progress(ctx.observer, "render", "samples", timed ? 0 : double(most) * pixels,
                              timed ? share : 0);
    progress.setPartitions(partitionProgress(st.partitions, nullptr, moves));
    CostBoundedSchedule estimates = ChainErrorMonitor::estimateSchedule();
    while (out.spp < most && !out.reachedTarget) {
        ctx.throwIfCancelled();
        const double elapsed = secondsSince(begin);
        if (timed && out.spp > 0 && (elapsed >= share || secondsSince(start) >= rs.budget)) break;
        const uint64_t n =
            nextPerPixelPass(ctx, out, most, out.spp > 0 ? elapsed / double(out.spp) : 0, previews,
                             share - elapsed, watch);
        out.renderer->renderPass({out.spp, out.spp + n}, progress);
        out.spp += n;
        if (reread && out.spp >= 2 && rereads.due()) {
            const auto rereading = Clock::now();
            out.pooledVariance =
                pooledVariance(st.pixelPilotVariance, st.pixelPilotSamples,
                               out.renderer->perSampleLuminanceVariance(out.spp), double(out.spp));
            out.share = rereadPixelShare(st.pixelShare, st.pixelPilotVariance, out.pooledVariance);
            share = out.share * timeLeft;
            rereads.ran(rereading);
        }
        // The estimate (the dashboard's error curves) after every pass while a target is
        // watched, else by the chains' monitor's rule (a 1280x720 image's partitions take a
        // tenth of a second to resolve); a preview after the first pass, then once per
        // interval.
        const bool estimate = watch || out.spp == n || estimates.due();
        const bool preview = out.spp < most && previews.due();
        if (!estimate && !preview) continue;
        const auto resolving = Clock::now();
        std::vector<Image> images = out.renderer->images(out.spp, &ctx.pool);
        if (estimate) {
            // No chains yet: the combined image's error only when every partition is per pixel.
            const ChainErrorMonitor::Estimate e = estimatePartitionError(
                st.partitions, nullptr, images, st.pixelVarianceRgb, out.spp);
            estimates.ran(resolving);  // its images' resolve included
            e.publish(progress);
            // With a target to watch, the render's own estimate stops it (trusted from 2 spp).
            out.reachedTarget =
                watch && out.spp >= 2 && e.combined >= 0 && e.combined <= targetError;
        }
        if (preview && !out.reachedTarget) {
            previewPerPixel(ctx, st, out, std::move(images), start);
            previews.shown(resolving);  // its images' resolve included
        }
    }
    progress.flush();
    out.seconds = secondsSince(begin);
    return out;
}

void addPerPixelStats(RenderStats& st, const PerPixelRun& run, double rays) {
    st.values["per_pixel_spp"] = double(run.spp);
    if (run.share >= 0) {
        st.values["per_pixel_share_reread"] = run.share;
        st.values["per_pixel_variance_pooled"] = run.pooledVariance;
    }
    st.values["per_pixel_seconds"] = run.seconds;
    st.values["per_pixel_rays"] = rays;
}

}  // namespace

RenderResult renderPartitioned(const RenderContext& ctx, const PartitionPipelineSettings& settings,
                               const std::string& algorithm, PartitionMutations& mutations) {
    const RenderSettings& rs = ctx.settings;
    auto start = Clock::now();
    const PartitionedStart st = startPartitioned(ctx, settings, algorithm, mutations);
    const std::vector<Partition>& partitions = st.partitions;
    // The per-pixel partitions first: the chains then get what is left of a time budget.
    const std::vector<std::string> moves = mutations.moves();
    PerPixelRun pixels = renderPerPixel(ctx, st, moves, start, settings.targetError);
    // Their film is given back here, and the renderer with what else it holds: the chains'
    // phase needs only its images.
    std::vector<Image> pixelImages =
        pixels.renderer ? pixels.renderer->takeImages(pixels.spp, &ctx.pool) : std::vector<Image>{};
    const double pixelRays = pixels.renderer ? double(pixels.renderer->rays()) : 0;
    pixels.renderer.reset();
    const double startupSeconds = st.startupSeconds + pixels.seconds;
    // The factory owns what the mutations read (guided's guides): it lives as long as the runner.
    const ChainRunner::MutationFactory factory = mutations.factory(ctx, partitions, st.prepared);
    // Each partition's odd chains get a film of their own (the error estimate).
    ChainRunner runner(ctx, st.plan, factory, restrictionsOf(partitions), settings.roundMutations,
                       ChainRunner::FilmLayout::PerGroupWithHalves);
    ChainErrorMonitor monitor(rs, settings.targetError, [&] {
        return estimatePartitionError(partitions, &runner, pixelImages, st.pixelVarianceRgb,
                                      pixels.spp);
    });
    auto imageOf = [&](uint32_t g) {
        return partitions[g].perPixel ? pixelImages[g] : runner.resolveGroupCombined(g);
    };
    // Every partition per pixel: no chains' phase (its progress would be an empty one).
    if (!st.plan.chains.empty())
        runChainsWithPreviews(
            ctx, runner, st.plan, startupSeconds,
            [&](ThreadPool*) {
                return resolvePartitions(imageOf, partitions, rs.width, rs.height);
            },
            [&](RenderStats& stats) { addPartitionStats(stats, partitions, progressOf(runner)); },
            [&](ProgressReporter& progress) {
                progress.setPartitions(partitionProgress(partitions, &runner, moves));
                monitor.afterRound(runner, progress);
            });

    RenderResult result;
    result.stats = st.stats;
    addChainStats(result.stats, runner, st.plan, secondsSince(start), startupSeconds,
                  st.startupRays + uint64_t(pixelRays), double(rs.width) * rs.height);
    addPartitionStats(result.stats, partitions, progressOf(runner));
    addPerPixelStats(result.stats, pixels, pixelRays);
    monitor.estimateNow();
    monitor.addStats(result.stats);
    if (pixels.reachedTarget) result.stats.values["reached_target_error"] = 1.0;
    // The statistics first: the image takes the chains' films, one partition at a time, so a
    // render's last moment holds the films or the images, not both (issue #24).
    result.image = resolvePartitions(
        [&](uint32_t g) {
            return partitions[g].perPixel ? std::move(pixelImages[g]) : runner.takeGroupCombined(g);
        },
        partitions, rs.width, rs.height);
    return result;
}

std::vector<uint8_t> PartitionedShards::plan(const RenderContext& ctx) {
    requireMutationBudget(ctx, algorithm_);
    if (settings_.targetError > 0)
        throw std::invalid_argument("a sharded " + algorithm_ +
                                    " job renders its whole budget: leave target_error at 0");
    return serializeStart(startPartitioned(ctx, settings_, algorithm_, mutations_));
}

uint32_t PartitionedShards::maxShards(const RenderContext&, std::span<const uint8_t> plan) const {
    // Every shard gets a chain; with no chain at all, a per-pixel sample.
    const PartitionedStart st = deserializeStart(plan);
    if (!st.plan.chains.empty())
        return uint32_t(std::min<size_t>(st.plan.chains.size(), UINT32_MAX));
    return uint32_t(std::clamp<uint64_t>(st.perPixelSpp, 1, UINT32_MAX));
}

ShardWork PartitionedShards::renderShard(const RenderContext& ctx, std::span<const uint8_t> bytes,
                                         uint32_t shard, uint32_t shards) {
    const PartitionedStart st = deserializeStart(bytes);
    // The factory owns what the mutations read (guided's guides): it lives as long as the runner.
    const ChainRunner::MutationFactory factory =
        mutations_.factory(ctx, st.partitions, st.prepared);
    ShardWork work = runChainShard(ctx, st.plan, shard, shards, factory,
                                   restrictionsOf(st.partitions), settings_.roundMutations);
    if (!st.anyPerPixel()) return work;
    // The per-pixel partitions' film comes last: this shard's range of their samples.
    PerPixelPartitions pixels(ctx, st.partitions, st.pixelEstimator);
    const ShareRange range = shareRange(st.perPixelSpp, shards, shard);
    const double pixelCount = double(ctx.settings.width) * ctx.settings.height;
    ProgressReporter progress(ctx.observer, "render", "samples",
                              double(range.count()) * pixelCount);
    pixels.renderPass({range.first, range.first + range.count()}, progress);
    progress.flush();
    work.sums["per_pixel_rays"] += double(pixels.rays());
    work.films.push_back(pixels.takeFilm());
    work.counts.push_back(range.count());
    return work;
}

RenderResult PartitionedShards::resolve(const RenderContext& ctx, std::span<const uint8_t> bytes,
                                        const ShardWork& merged) {
    const PartitionedStart st = deserializeStart(bytes);
    const RenderSettings& rs = ctx.settings;
    const size_t films = st.partitions.size() + (st.anyPerPixel() ? 1 : 0);
    if (merged.films.size() != films)
        throw std::invalid_argument("merged work has " + std::to_string(merged.films.size()) +
                                    " films for " + std::to_string(st.partitions.size()) +
                                    " partitions");
    const std::vector<Image> pixelImages =
        st.anyPerPixel() ? perPixelImages(merged.films.back(), st.partitions, merged.counts.back())
                         : std::vector<Image>{};
    auto imageOf = [&](uint32_t g) {
        if (st.partitions[g].perPixel) return pixelImages[g];
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
    if (st.anyPerPixel()) {
        result.stats.values["per_pixel_spp"] = double(merged.counts.back());
        result.stats.values["rays"] += sum("per_pixel_rays");
    }
    addPartitionStats(result.stats, st.partitions, groups);
    return result;
}

}  // namespace partita
