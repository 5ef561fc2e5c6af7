#include "partition/effort_pilot.h"

#include <algorithm>
#include <stdexcept>

#include "image_metrics.h"
#include "mcmc/bootstrap.h"
#include "partition/partition_chains.h"
#include "partition/per_pixel_partitions.h"
#include "progress_reporter.h"

namespace partita {

namespace {

constexpr uint64_t kPilotSalt = 1;
/// A mutation budget's pilot at most this many mutations per pixel: enough for the halves'
/// difference to show each partition's error (at 256x192, ~200000 mutations), while a share of
/// a long job's budget would spend minutes on chains that are thrown away.
constexpr double kMaxPilotMpp = 4;

/// Splits each group g of `plan` in two: group 2g gets g's even chains, 2g + 1 its odd ones
/// (the same b: two independent halves of the partition's estimate).
ChainPlan intoHalves(ChainPlan plan) {
    std::vector<ChainGroup> groups;
    for (const ChainGroup& g : plan.groups) {
        groups.push_back({g.label + " (even)", g.b});
        groups.push_back({g.label + " (odd)", g.b});
    }
    std::vector<uint64_t> seen(plan.groups.size(), 0);
    for (PlannedChain& c : plan.chains) c.group = 2 * c.group + uint32_t(seen[c.group]++ % 2);
    plan.groups = std::move(groups);
    return plan;
}

/// The pilot's chains of partition g alone, in two halves (groups 0 and 1): a plan with g's
/// mutations only, its other groups dropped (a runner makes a film for every group).
ChainPlan pilotPlanOf(const RenderContext& ctx, const BootstrapSampler& sampler,
                      const PrepassResult& prepass, const std::vector<Partition>& partitions,
                      size_t g, uint64_t mutations, const PartitionPipelineSettings& s) {
    std::vector<uint64_t> counts(partitions.size(), 0);
    counts[g] = mutations;
    // Each partition's own salt: its chains' streams independent of the others'.
    ChainPlan plan = intoHalves(
        planPartitionChains(ctx, sampler, prepass, partitions, counts, s, kPilotSalt + g));
    plan.groups = {plan.groups[2 * g], plan.groups[2 * g + 1]};
    for (PlannedChain& c : plan.chains) c.group -= uint32_t(2 * g);
    return plan;
}

/// v_g of the header from a runner of one partition's two halves, or -1 when a half ran no
/// mutation.
double halvesVariance(const ChainRunner& runner) {
    const uint64_t ma = runner.mutationsDone(0), mb = runner.mutationsDone(1);
    if (ma == 0 || mb == 0) return -1;
    const double sum =
        luminanceSquaredDifference(runner.resolveGroupCombined(0), runner.resolveGroupCombined(1));
    return sum / (1.0 / double(ma) + 1.0 / double(mb));
}

/// The chains' pilot of one move: v_g and c_g of every partition with chains (-1 and 0 for the
/// others), its rays and mutations. One partition at a time, each with the same share of the
/// pilot (each one's error is measured alike) and its share of the chains: two films (its
/// halves) alive at once, not two per partition (at 1280x720, 24 films of 22 MB).
ChainPilot chainPilot(const RenderContext& ctx, const BootstrapSampler& sampler,
                      const PrepassResult& prepass, const std::vector<Partition>& partitions,
                      const ChainRunner::MutationFactory& mutations,
                      const ChainRunner::RestrictionFactory& restrictions,
                      const PartitionPipelineSettings& s, double secondsLeft) {
    const RenderSettings& rs = ctx.settings;
    const bool timed = rs.budgetKind == BudgetKind::Seconds;
    ChainPilot out;
    out.variance.assign(partitions.size(), -1);
    out.cost.assign(partitions.size(), 0);
    // The direct light is per pixel whatever the pilots say: no chains to measure.
    std::vector<size_t> measured;
    for (size_t g = 0; g < partitions.size(); ++g)
        if (!partitions[g].direct) measured.push_back(g);
    if (measured.empty()) return out;
    const double pixels = double(rs.width) * rs.height;
    const double pilotMpp = std::min(s.pilotShare * rs.budget, kMaxPilotMpp);
    const uint64_t perPartition =
        timed ? (uint64_t(1) << 40)
              : std::max<uint64_t>(4 * s.minMutationsPerChain,
                                   uint64_t(pilotMpp * pixels / double(partitions.size())));
    PartitionPipelineSettings one = s;
    one.chains = std::max(2, s.chains / int(measured.size()));
    const double seconds = timed ? std::max(1e-3, s.pilotShare * secondsLeft) : 0;
    ProgressReporter progress(ctx.observer, "pilot", "mutations",
                              timed ? 0 : double(perPartition * measured.size()), seconds);
    // The chains' running time only, as when every partition's ran at once: not each
    // partition's plan and chain set-up (regenerating its starts).
    double chainSeconds = 0;
    std::vector<uint64_t> done(partitions.size(), 0), rays(partitions.size(), 0);
    for (size_t g : measured) {
        const ChainPlan plan = pilotPlanOf(ctx, sampler, prepass, partitions, g, perPartition, one);
        ChainRunner runner(
            ctx, plan, [&](uint32_t) { return mutations(uint32_t(g)); },
            [&](uint32_t) { return restrictions(uint32_t(g)); }, s.roundMutations);
        const auto running = Clock::now();
        runner.run(progress, timed ? seconds / double(measured.size()) : 0);
        chainSeconds += secondsSince(running);
        out.variance[g] = halvesVariance(runner);
        done[g] = runner.mutationsDone();
        rays[g] = runner.rays();
        ctx.throwIfCancelled();
    }
    progress.flush();
    for (size_t g : measured) {
        out.rays += rays[g];
        out.mutations += done[g];
    }
    const double secondsPerRay = out.rays > 0 ? chainSeconds / double(out.rays) : 0;
    const double unit = timed ? secondsPerRay : 1.0;  // a cost in seconds, or in rays
    out.mutationCost = out.mutations > 0 ? double(out.rays) / double(out.mutations) * unit : 0;
    for (size_t g : measured)
        out.cost[g] = done[g] > 0 ? double(rays[g]) / double(done[g]) * unit : out.mutationCost;
    return out;
}

/// Each partition's move (the one of least v_g c_g; the first on a tie or where a pilot
/// measured nothing) and its v_g and c_g into `out`; the mean cost of a pilot mutation.
void chooseMoves(EffortMeasurement& out) {
    const size_t n = out.partitions.size();
    out.move.assign(n, 0);
    uint64_t rays = 0, mutations = 0;
    for (const ChainPilot& pilot : out.movePilots) {
        rays += pilot.rays;
        mutations += pilot.mutations;
    }
    out.chainMutations = mutations;
    double worst = 0;  // the largest measured v_g: for a partition whose halves did not both run
    for (size_t g = 0; g < n; ++g) {
        for (size_t k = 1; k < out.movePilots.size(); ++k) {
            const ChainPilot &best = out.movePilots[out.move[g]], &other = out.movePilots[k];
            if (other.variance[g] >= 0 &&
                (best.variance[g] < 0 ||
                 other.variance[g] * other.cost[g] < best.variance[g] * best.cost[g]))
                out.move[g] = uint8_t(k);
        }
        const ChainPilot& chosen = out.movePilots[out.move[g]];
        PartitionEffort& e = out.partitions[g];
        e.chainVariance = chosen.variance[g];
        e.mutationCost = chosen.cost[g] > 0 ? chosen.cost[g] : chosen.mutationCost;
        worst = std::max(worst, e.chainVariance);
    }
    for (PartitionEffort& e : out.partitions)
        if (e.chainVariance < 0) e.chainVariance = worst > 0 ? worst : 1.0;
    // The mean cost of a pilot mutation, over every move's (each in its pilot's units).
    double weighted = 0;
    for (const ChainPilot& pilot : out.movePilots)
        weighted += pilot.mutationCost * double(pilot.mutations);
    out.mutationCost = mutations > 0 ? weighted / double(mutations) : 0;
    out.rays += rays;
}

}  // namespace

EffortMeasurement measureEffort(const RenderContext& ctx, const BootstrapSampler& sampler,
                                const PrepassResult& prepass,
                                const std::vector<Partition>& partitions,
                                const std::vector<ChainRunner::MutationFactory>& moves,
                                const ChainRunner::RestrictionFactory& restrictions,
                                const PartitionPipelineSettings& settings, EstimatorChoice choice,
                                double secondsLeft) {
    auto begin = Clock::now();
    const bool timed = ctx.settings.budgetKind == BudgetKind::Seconds;
    EffortMeasurement out;
    out.partitions.resize(partitions.size());
    for (size_t g = 0; g < partitions.size(); ++g) {
        out.partitions[g].p = partitions[g].p;
        out.partitions[g].b = partitions[g].b;
        out.partitions[g].alwaysPerPixel = partitions[g].direct;
    }
    if (choice != EstimatorChoice::Chains) {
        // The per-pixel estimators piloted (pixel_estimator: one, or both with "pilot"), each
        // with its samples per parity (runPerPixelPilot's k). A path tracer cannot reach a
        // delta light through specular chains: bdpt only then. (A bdpt pilot over a quarter of
        // the pixels, tried to save its cost, saw 2.5x less variance than over all of them on
        // cornell-glass: a few pixels hold most of it.)
        std::vector<std::pair<PerPixelEstimator, uint64_t>> estimators;
        std::string why;
        const bool ptMay =
            choosePrepassEstimator(ctx.scene, "auto", why) == StartupEstimator::PathTracer;
        if (settings.pixelEstimator == "pt" && !ptMay)
            throw std::invalid_argument(
                "pixel_estimator=pt: the path tracer cannot reach this scene's delta lights "
                "through specular surfaces; use bdpt or auto");
        const std::string& asked = settings.pixelEstimator;
        const bool pt = asked == "pt" || (ptMay && (asked == "auto" || asked == "pilot"));
        if (pt) estimators.push_back({PerPixelEstimator::PathTracer, kPathTracerPilotSamples});
        if (asked == "bdpt" || asked == "pilot" || !pt)
            estimators.push_back({PerPixelEstimator::Bdpt, 1});
        const double pixels = perPixelPilotTiles(ctx.settings.width, ctx.settings.height).pixels;
        double samples = 0;
        for (const auto& [estimator, k] : estimators) samples += 2 * double(k) * pixels;
        ProgressReporter progress(ctx.observer, "pilot", "samples", samples);
        for (const auto& [estimator, k] : estimators) {
            const PerPixelPilot pilot =
                runPerPixelPilot(ctx, partitions, estimator, kPerPixelPilotSample, progress, k);
            out.pixelPilots.push_back({estimator, pilot.variance,
                                       timed ? pilot.secondsPerSample : pilot.raysPerSample,
                                       pilot.varianceRgb, 2 * double(k)});
            out.rays += uint64_t(2 * double(k) * pilot.raysPerSample);
            ctx.throwIfCancelled();
        }
        progress.flush();
    }
    if (choice != EstimatorChoice::PerPixel && !moves.empty()) {
        // Each move gets a whole pilot on the same partitions: with half each, the allocation's
        // v_g were noisier and guided lost 5-10% of RMSE at 10 s (docs/partition-estimators.md,
        // "Where the guided move pays").
        const double left = std::max(0.0, secondsLeft - secondsSince(begin));
        for (const ChainRunner::MutationFactory& mutations : moves)
            out.movePilots.push_back(chainPilot(ctx, sampler, prepass, partitions, mutations,
                                                restrictions, settings, left));
        chooseMoves(out);
    }
    out.seconds = secondsSince(begin);
    return out;
}

}  // namespace partita
