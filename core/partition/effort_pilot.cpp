#include "partition/effort_pilot.h"

#include <algorithm>

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

/// v_g of the header, or -1 when a half ran no mutation.
double halvesVariance(const ChainRunner& runner, uint32_t g) {
    const uint64_t ma = runner.mutationsDone(int(2 * g)), mb = runner.mutationsDone(int(2 * g + 1));
    if (ma == 0 || mb == 0) return -1;
    const double sum = luminanceSquaredDifference(runner.resolveGroupCombined(2 * g),
                                                  runner.resolveGroupCombined(2 * g + 1));
    return sum / (1.0 / double(ma) + 1.0 / double(mb));
}

/// The chains' pilot: v_g and c_g of every partition into `out`.
void chainPilot(const RenderContext& ctx, const BootstrapSampler& sampler,
                const PrepassResult& prepass, const std::vector<Partition>& partitions,
                const ChainRunner::MutationFactory& mutations,
                const ChainRunner::RestrictionFactory& restrictions,
                const PartitionPipelineSettings& s, double secondsLeft, EffortMeasurement& out) {
    const RenderSettings& rs = ctx.settings;
    const bool timed = rs.budgetKind == BudgetKind::Seconds;
    const size_t n = partitions.size();
    // The same share of the pilot for every partition: each one's error is measured alike.
    const double pixels = double(rs.width) * rs.height;
    const double pilotMpp = std::min(s.pilotShare * rs.budget, kMaxPilotMpp);
    const uint64_t perPartition = timed
                                      ? (uint64_t(1) << 40)
                                      : std::max<uint64_t>(4 * s.minMutationsPerChain,
                                                           uint64_t(pilotMpp * pixels / double(n)));
    // The direct light is per pixel whatever the pilots say: no chains to measure.
    std::vector<uint64_t> counts(n, perPartition);
    for (size_t g = 0; g < n; ++g)
        if (partitions[g].direct) counts[g] = 0;
    const ChainPlan plan =
        intoHalves(planPartitionChains(ctx, sampler, prepass, partitions, counts, s, kPilotSalt));
    auto halfOf = [](uint32_t group) { return group / 2; };
    ChainRunner runner(
        ctx, plan, [&](uint32_t group) { return mutations(halfOf(group)); },
        [&](uint32_t group) { return restrictions(halfOf(group)); }, s.roundMutations);
    const double seconds = timed ? std::max(1e-3, s.pilotShare * secondsLeft) : 0;
    auto begin = Clock::now();
    ProgressReporter progress(ctx.observer, "pilot", "mutations",
                              timed ? 0 : double(plan.mutations()), seconds);
    runner.run(progress, seconds);
    progress.flush();
    const double chainSeconds = secondsSince(begin);
    const double secondsPerRay = runner.rays() > 0 ? chainSeconds / double(runner.rays()) : 0;
    out.rays += runner.rays();
    out.chainMutations = runner.mutationsDone();
    out.mutationCost = out.chainMutations > 0 ? double(runner.rays()) / double(out.chainMutations) *
                                                    (timed ? secondsPerRay : 1.0)
                                              : 0;
    double worst = 0;  // the largest measured v_g: for a partition whose halves did not both run
    for (size_t g = 0; g < n; ++g) {
        PartitionEffort& e = out.partitions[g];
        e.chainVariance = halvesVariance(runner, uint32_t(g));
        worst = std::max(worst, e.chainVariance);
        const uint64_t done =
            runner.mutationsDone(int(2 * g)) + runner.mutationsDone(int(2 * g + 1));
        const double rays = double(runner.rays(int(2 * g)) + runner.rays(int(2 * g + 1)));
        e.mutationCost =
            done > 0 ? rays / double(done) * (timed ? secondsPerRay : 1.0) : out.mutationCost;
    }
    for (PartitionEffort& e : out.partitions)
        if (e.chainVariance < 0) e.chainVariance = worst > 0 ? worst : 1.0;
}

}  // namespace

EffortMeasurement measureEffort(const RenderContext& ctx, const BootstrapSampler& sampler,
                                const PrepassResult& prepass,
                                const std::vector<Partition>& partitions,
                                const ChainRunner::MutationFactory& mutations,
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
        std::vector<PerPixelEstimator> estimators{PerPixelEstimator::Bdpt};
        // A path tracer cannot reach a delta light through specular chains: bdpt only then.
        std::string why;
        if (choosePrepassEstimator(ctx.scene, "auto", why) == StartupEstimator::PathTracer)
            estimators.push_back(PerPixelEstimator::PathTracer);
        // The pilot's pixels: perhaps part of the image.
        const double pixels = perPixelPilotTiles(ctx.settings.width, ctx.settings.height).pixels;
        ProgressReporter progress(ctx.observer, "pilot", "samples",
                                  2 * pixels * double(estimators.size()));
        for (PerPixelEstimator estimator : estimators) {
            const PerPixelPilot pilot =
                runPerPixelPilot(ctx, partitions, estimator, kPerPixelPilotSample, progress);
            out.pixelPilots.push_back({estimator, pilot.variance,
                                       timed ? pilot.secondsPerSample : pilot.raysPerSample,
                                       pilot.varianceRgb});
            out.rays += uint64_t(2 * pilot.raysPerSample);
            ctx.throwIfCancelled();
        }
        progress.flush();
    }
    if (choice != EstimatorChoice::PerPixel)
        chainPilot(ctx, sampler, prepass, partitions, mutations, restrictions, settings,
                   std::max(0.0, secondsLeft - secondsSince(begin)), out);
    out.seconds = secondsSince(begin);
    return out;
}

}  // namespace partita
