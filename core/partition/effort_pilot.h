// The start-up's pilots that measure what each estimator would give a partition (issue #23 1, 3;
// the formulas in effort_plan.h). Both are independent of the render's own samples and are not
// part of its image:
// - the per-pixel pilots: two samples of every pixel (per_pixel_partitions.h), V_g per partition,
//   by BDPT and, in a scene without delta lights, by the path tracer;
// - the chains' pilot: every partition's chains in two halves (groups 2g and 2g + 1, other
//   starts and streams than the render's), for a share of the budget; the halves' difference
//   gives the error of partition g's image after its m_g mutations, and v_g = that error
//   divided by (1 / m_a + 1 / m_b) (independent halves of m_a and m_b mutations, each of
//   variance v / m).
// Costs are rays for a mutation budget (so that the choice, and the image, do not depend on the
// machine or the threads) and seconds for a time budget.
#pragma once

#include <cstdint>
#include <vector>

#include "algorithm.h"
#include "clock.h"
#include "mcmc/chain_runner.h"
#include "partition/effort_plan.h"
#include "partition/partition.h"
#include "partition/per_pixel_partitions.h"
#include "partition/pipeline_settings.h"
#include "partition/prepass.h"

namespace partita {

class BootstrapSampler;

/// One per-pixel estimator's pilot: V_g per partition and c_pp.
struct PixelPilot {
    PerPixelEstimator estimator = PerPixelEstimator::Bdpt;
    std::vector<double> variance;
    double cost = 0;
    std::vector<double> varianceRgb;  // PerPixelPilot's
    double samplesPerPixel = 0;       // 2k: the samples its variances were measured from
};

/// The chains' pilot of one move: per partition v_g and c_g (-1 and 0 where it ran no chains).
struct ChainPilot {
    std::vector<double> variance, cost;
    double mutationCost = 0;  // the mean over its partitions
    uint64_t rays = 0, mutations = 0;
};

struct EffortMeasurement {
    /// pixelVariance left 0: each per-pixel estimator's is in `pixelPilots`.
    std::vector<PartitionEffort> partitions;
    /// bdpt's, then the path tracer's where it applies (no delta light).
    std::vector<PixelPilot> pixelPilots;
    /// The chains' pilot of each move (PartitionMutations::moves; one when there is nothing
    /// to choose), and per partition the move chosen: the one of least v_g c_g, whose v_g and
    /// c_g are in `partitions`.
    std::vector<ChainPilot> movePilots;
    std::vector<uint8_t> move;
    double mutationCost = 0;  // the mean cost of one pilot mutation, every partition and move
    double seconds = 0;       // both pilots
    uint64_t rays = 0;
    uint64_t chainMutations = 0;  // the chains' pilot's
};

/// Runs the pilots `choice` needs (none of the per-pixel one for "chains", none of the chains'
/// for "per-pixel"). A time budget's chains' pilot runs for `pilotShare` of `secondsLeft`; a
/// mutation budget's for pilotShare of its mutations (at most 4 per pixel), spread evenly over
/// the partitions; with several `moves` (a mutation factory each) each move gets such a pilot.
/// Phase "pilot"; cancellable.
EffortMeasurement measureEffort(const RenderContext& ctx, const BootstrapSampler& sampler,
                                const PrepassResult& prepass,
                                const std::vector<Partition>& partitions,
                                const std::vector<ChainRunner::MutationFactory>& moves,
                                const ChainRunner::RestrictionFactory& restrictions,
                                const PartitionPipelineSettings& settings, EstimatorChoice choice,
                                double secondsLeft);

/// The sample index of the per-pixel pilot's first sample: far from any image's own.
inline constexpr uint64_t kPerPixelPilotSample = uint64_t(1) << 40;
/// The path tracer's pilot samples per parity (runPerPixelPilot's k): enough of its stratified
/// samples to show their gain on the light seen directly and through glass. BDPT's takes 1 (a
/// sample costs it 4-9x more, and its light-traced part gains nothing from the pixel's strata).
inline constexpr uint64_t kPathTracerPilotSamples = 4;

}  // namespace partita
