// Which estimator each partition gets and how much of the budget (issue #23 1 and 3).
//
// Partition g can be integrated by its chains or per pixel (per_pixel_partitions.h). Each has,
// measured by the start-up's pilots, an error that falls as 1 / effort:
// - chains: E_g = v_g / m_g after m_g mutations (v_g: the image error of the pilot chains, sum
//   over pixels of the luminance variance, times their mutations), each costing c_g;
// - per pixel: E = V_g / n after n samples of every pixel (V_g: the pilot's one-sample image
//   error), one sample of every pixel costing c_pp, shared by every per-pixel partition (one
//   BDPT sample estimates all of them).
// With cost T_g spent on partition g's chains, E_g = A_g / T_g, A_g = v_g c_g; with T_pp on the
// per-pixel samples, E_pp = A_pp / T_pp, A_pp = c_pp sum_{g per pixel} V_g. The total error
// sum A / T over these strata, with their costs summing to T, is smallest at
//     T_i = T sqrt(A_i) / sum_j sqrt(A_j)                                  (Neyman allocation)
// and is then (sum_j sqrt(A_j))^2 / T (Neyman 1934; Cochran, "Sampling Techniques", 1977,
// Sec. 5.5, the optimum allocation n_h proportional to N_h S_h / sqrt(c_h)).
//
// The choice ("auto"): the per-pixel set S minimising the total error at the optimum,
//     F(S) = sum_{g not in S} sqrt(A_g) + sqrt(c_pp sum_{g in S} V_g),
// over every subset when there are at most kExhaustivePartitions partitions, else over the
// prefixes of the partitions ranked by sqrt(A_g) / V_g (the relaxed problem's solution). A
// partition the per-pixel pilot did not see (V_g = 0 with b_g > 0: none of its light reached a
// pilot sample) keeps its chains: two samples cannot vouch for it. Ties keep chains. A partition
// `alwaysPerPixel` (the direct light) is in S whatever the choice.
//
// "p" is the paper's Eq. 10: every partition has chains, their mutations in proportion to P(i).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace partita {

enum class EstimatorChoice { Auto, Chains, PerPixel };
/// "auto", "chains", "per-pixel"; std::invalid_argument otherwise.
EstimatorChoice parseEstimatorChoice(const std::string& name);

/// A partition's measured inputs (see above).
struct PartitionEffort {
    double p = 0;                 // P(i)
    double b = 0;                 // b_i
    double chainVariance = 0;     // v_g: chain error times mutations
    double mutationCost = 0;      // c_g
    double pixelVariance = 0;     // V_g: the per-pixel error with one sample of every pixel
    bool alwaysPerPixel = false;  // the direct light (partition.h): per pixel whatever the choice
};

struct EffortPlan {
    std::vector<bool> perPixel;       // per partition
    std::vector<double> chainShare;   // per partition: its chains' share of the cost (0: none)
    double pixelShare = 0;            // the per-pixel samples' share of the cost
    std::vector<std::string> reason;  // per partition, why it got its estimator
    /// The formula's total error at the plan's shares, times the total cost:
    /// sum over strata of A_i / share_i (Neyman's optimum: (sum sqrt(A_i))^2).
    double errorTimesCost = 0;
};

inline constexpr size_t kExhaustivePartitions = 16;

/// The plan for `partitions` with per-pixel sample cost `pixelCost` (c_pp). `neyman` false: the
/// shares in proportion to P(i) (Eq. 10), every partition with chains.
EffortPlan planEffort(const std::vector<PartitionEffort>& partitions, double pixelCost,
                      EstimatorChoice choice, bool neyman);

/// sum over the strata of A_i / share_i for the given estimators and shares (infinite when a
/// stratum with A_i > 0 has no share).
double errorTimesCost(const std::vector<PartitionEffort>& partitions, double pixelCost,
                      const std::vector<bool>& perPixel, const std::vector<double>& chainShare,
                      double pixelShare);

/// The plan's per-pixel share `planShare` (of the time, at the pilot's stratum variance V) with
/// V' in its place and the partitions' estimators unchanged: sqrt(A_pp) scales by sqrt(V' / V)
/// and the chains' sum of sqrt(A_g), sqrt(A_pp) (1 - f) / f, stays: the share planEffort gives
/// with V'. planShare must be in (0, 1).
double rereadPixelShare(double planShare, double pilotVariance, double variance);

}  // namespace partita
