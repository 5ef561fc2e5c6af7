// One Markov chain over path space (paper Eq. 3 with Veach's mutations): the per-chain stepping
// that mlt, partitioned and guided share. Each step picks one of the mutations that apply to the
// current path, proposes, and accepts with metropolis.h's step; the probability of the choice
// enters the acceptance both ways, as it depends on the path. A mutation with a fixed rate (the
// independence mutation's large-step rate) is chosen with that probability whenever it applies;
// the others share the rest in proportion to their weights among those that apply:
//     P(m | x) = rate_m                                 (m fixed-rate, applies to x)
//     P(m | x) = (1 - F(x)) w_m / W(x)                  (otherwise)
// with F(x) the sum of the rates and W(x) that of the weights of the mutations that apply to x. A
// restriction (a partition, paper Sec. 4) rejects every proposal whose type it excludes.
// Expected-value splats: each step hands both states to the caller with their weights, as f(x) /
// f*(x) times the weight, to be scaled by b / N when the image is resolved.
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
    double weight;  // a share among the weighted mutations, or the rate when fixedRate
    bool fixedRate = false;
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
        return stepWith([&](const MarkovPath& s, double weight) {
            splat(s.raster, s.type, s.f * float(weight / double(s.fStar)));
        });
    }

    /// step() with the current state's splats deferred: while the chain stays, its weights
    /// (1 - a a step) add up and reach `splat` as one splat when it moves, or at flush(); a
    /// proposal that is accepted starts that sum with its own weight a instead of a splat of its
    /// own. The image is the same sum with one film add per move and one per rejected proposal,
    /// instead of two per step (the film's adds are a chain's largest cost after tracing, issue
    /// #22 4). Call flush(splat) before the splats are read.
    template <typename Splat>
    bool stepDeferred(Splat&& splat) {
        PendingSplat proposal;
        auto splatState = [&](const MarkovPath& s, double weight) {
            if (&s != &current_) {
                proposal = {s.raster, s.type, s.f, double(s.fStar), weight};
                return;
            }
            if (pending_.weight == 0) pending_ = {s.raster, s.type, s.f, double(s.fStar), 0};
            pending_.weight += weight;
        };
        bool moved = stepWith(splatState);
        if (moved) {
            flush(splat);
            pending_ = proposal;  // the new current state, with its weight a of this step
        } else if (proposal.weight > 0) {
            splatPending(proposal, splat);
        }
        return moved;
    }
    /// Hands the current state's deferred weight (stepDeferred) to `splat`.
    template <typename Splat>
    void flush(Splat&& splat) {
        splatPending(pending_, splat);
        pending_.weight = 0;
    }

    const MarkovPath& state() const { return current_; }
    const std::vector<MutationStats>& stats() const { return stats_; }
    uint64_t rays() const { return rays_; }

  private:
    /// One mutation, each state handed to splatState(state, expected-value weight).
    template <typename SplatState>
    bool stepWith(SplatState&& splatState) {
        size_t chosen = SIZE_MAX;
        auto propose = [&](const MarkovPath& x, Rng& rng) {
            Proposal<MarkovPath> y;
            y.valid = proposeWithChoice(x, rng, y.state, y.reverseOverForward, chosen);
            y.f = y.state.fStar;
            return y;
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
    /// Chooses a mutation among those that apply to x and proposes with it; the ratio includes
    /// P(choice | y) / P(choice | x) and the restriction. `chosen` is set whenever one applied.
    bool proposeWithChoice(const MarkovPath& x, Rng& rng, MarkovPath& y, double& ratio,
                           size_t& chosen);
    /// The total weight of the weighted mutations that apply to p: W(p) of the header.
    double applicableWeight(const MarkovPath& p) const;
    /// The total rate of the fixed-rate mutations that apply to p: F(p) of the header.
    double applicableRate(const MarkovPath& p) const;
    /// The index of the mutation a uniform u chooses at x (SIZE_MAX: none).
    size_t choose(const MarkovPath& x, double u) const;

    std::vector<WeightedMutation> mutations_;
    PathRestriction restriction_;
    MarkovPath current_;
    Rng rng_;
    std::vector<MutationStats> stats_;
    uint64_t rays_ = 0;
    /// A splat that stepDeferred holds back: f / f* times the summed weight.
    struct PendingSplat {
        Vec2f raster;
        PathType type;
        Rgb f;
        double fStar = 1;
        double weight = 0;
    };
    template <typename Splat>
    static void splatPending(const PendingSplat& p, Splat&& splat) {
        if (p.weight > 0) splat(p.raster, p.type, p.f * float(p.weight / p.fStar));
    }
    PendingSplat pending_;  // the current state's
};

}  // namespace partita
