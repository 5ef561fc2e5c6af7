// Veach's four mutations and the independence (large-step) mutation, with their settings and the
// probabilities of choosing them: the mutation set of `mlt`, `partitioned` and `guided`.
#pragma once

#include <memory>
#include <vector>

#include "mcmc/bidirectional_mutation.h"
#include "mcmc/markov_chain.h"
#include "mcmc/perturbation_sizes.h"

namespace partita {

class Camera;
class RenderScene;

struct VeachMutationSettings {
    // Choice weights, renormalised over the mutations that apply to the current path.
    double bidirectionalWeight = 1, lensWeight = 1, causticWeight = 1, multiChainWeight = 1;
    BidirectionalSettings bidirectional;
    /// Lens and multi-chain raster offsets: from 0.1 pixel to this fraction of the image's
    /// larger side (Veach: r1 = 0.1 pixel, r2 = a tenth of the image).
    float lensSmallestPixels = 0.1f, lensLargestFraction = 0.1f;
    /// Caustic and multi-chain deflections, radians (Veach: 1e-4 .. 0.1).
    PerturbationRange causticAngles{1e-4f, 0.1f}, multiChainAngles{1e-4f, 0.1f};
    /// The independence mutation's rate: the probability of a fresh path at every step, the
    /// four others sharing the rest by their weights (markov_chain.h). Parameter
    /// "large_step_rate"; the default measured in docs/mlt-study.md ("Suspicious" 2).
    double largeStepRate = kDefaultLargeStepRate;
    /// The path lengths (vertices) it proposes; empty: every length the maximum depth allows.
    /// A chain's restriction may leave out some (mlt's indirect chains: n >= 4).
    std::vector<int> independenceVertexCounts;
    static constexpr double kDefaultLargeStepRate = 0.1;
};

/// Mutations owned together, with their weights, for one chain.
struct MutationSet {
    std::vector<std::unique_ptr<Mutation>> owned;
    std::vector<WeightedMutation> weighted;
    void add(std::unique_ptr<Mutation> m, double weight, bool fixedRate = false) {
        weighted.push_back({m.get(), weight, fixedRate});
        owned.push_back(std::move(m));
    }
};

/// The lens and multi-chain perturbations' raster offset sizes for `camera`.
PerturbationRange lensPixelRange(const Camera& camera, const VeachMutationSettings& settings);

/// Veach's four mutations; `lens`, when given, takes the lens perturbation's place (with its
/// weight): guided's image perturbation (guide/guided_perturbation.h).
MutationSet makeVeachMutations(const RenderScene& scene, const Camera& camera, int maxDepth,
                               const VeachMutationSettings& settings,
                               std::unique_ptr<Mutation> lens = nullptr);

}  // namespace partita
