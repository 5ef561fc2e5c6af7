// One Markov chain over path space (paper Eq. 3 with Veach's mutations): the per-chain stepping
// that mlt, partitioned and guided share. Each step picks one of the mutations that apply to the
// current path (with probability proportional to its weight among them), proposes, and accepts
// with metropolis.h's step; the probability of the choice enters the acceptance both ways, as
// it depends on the path. A restriction (a partition, paper Sec. 4) rejects every proposal whose
// type it excludes. Expected-value splats: each step hands both states to the caller with their
// weights, as f(x) / f*(x) times the weight, to be scaled by b / N when the image is resolved.
//
// A chain's result depends only on its start, its RNG and its mutation count: chains can run in
// any order, on any thread, or in another process.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "mcmc/markov_path.h"
#include "mcmc/metropolis.h"
#include "mcmc/mutation.h"
#include "rng.h"

namespace partita {

struct WeightedMutation {
    Mutation* mutation;
    double weight;
};

/// Which paths a chain may visit; an empty function allows every path.
using PathRestriction = std::function<bool(const PathType&)>;

struct MutationStats {
    uint64_t proposed = 0;  // times the mutation was chosen
    uint64_t accepted = 0;  // times the chain moved
    double acceptance = 0;  // sum of the acceptance probabilities a
};

class MarkovChain {
  public:
    /// `start` must carry a non-zero f* and satisfy the restriction.
    MarkovChain(std::vector<WeightedMutation> mutations, PathRestriction restriction,
                MarkovPath start, Rng rng);

    /// One mutation. splat(raster, type, value) receives each state's f / f* times its
    /// expected-value weight. Returns whether the chain moved.
    template <typename Splat>
    bool step(Splat&& splat) {
        size_t chosen = SIZE_MAX;
        auto propose = [&](const MarkovPath& x, Rng& rng) {
            Proposal<MarkovPath> y;
            y.valid = proposeWithChoice(x, rng, y.state, y.reverseOverForward, chosen);
            y.f = y.state.fStar;
            return y;
        };
        auto splatState = [&](const MarkovPath& s, double weight) {
            splat(s.raster, s.type, s.f * float(weight / double(s.fStar)));
        };
        double fx = current_.fStar;
        bool moved = false;
        double a = metropolisStep(current_, fx, rng_, propose, splatState, &moved);
        if (chosen < stats_.size()) {
            MutationStats& st = stats_[chosen];
            ++st.proposed;
            st.acceptance += a;
            st.accepted += moved;
        }
        return moved;
    }

    const MarkovPath& state() const { return current_; }
    const std::vector<MutationStats>& stats() const { return stats_; }
    uint64_t rays() const { return rays_; }

  private:
    /// Chooses a mutation among those that apply to x and proposes with it; the ratio includes
    /// P(choice | y) / P(choice | x) and the restriction. `chosen` is set whenever one applied.
    bool proposeWithChoice(const MarkovPath& x, Rng& rng, MarkovPath& y, double& ratio,
                           size_t& chosen);
    /// The total weight of the mutations that apply to p.
    double applicableWeight(const MarkovPath& p) const;

    std::vector<WeightedMutation> mutations_;
    PathRestriction restriction_;
    MarkovPath current_;
    Rng rng_;
    std::vector<MutationStats> stats_;
    uint64_t rays_ = 0;
};

}  // namespace partita
