#include "mcmc/markov_chain.h"

#include <algorithm>
#include <cstdint>

namespace partita {

MarkovChain::MarkovChain(std::vector<WeightedMutation> mutations, PathRestriction restriction,
                         MarkovPath start, Rng rng)
    : mutations_(std::move(mutations)),
      restriction_(std::move(restriction)),
      current_(std::move(start)),
      rng_(rng),
      stats_(mutations_.size()) {}

double MarkovChain::applicableWeight(const MarkovPath& p) const {
    double total = 0;
    for (const WeightedMutation& m : mutations_)
        if (!m.fixedRate && m.weight > 0 && m.mutation->appliesTo(p)) total += m.weight;
    return total;
}

double MarkovChain::applicableRate(const MarkovPath& p) const {
    double total = 0;
    for (const WeightedMutation& m : mutations_)
        if (m.fixedRate && m.weight > 0 && m.mutation->appliesTo(p)) total += m.weight;
    return std::min(total, 1.0);
}

size_t MarkovChain::choose(const MarkovPath& x, double u) const {
    // The fixed-rate mutations first, each covering its rate of [0, 1).
    double rateX = applicableRate(x), running = 0;
    if (u < rateX) {
        for (size_t i = 0; i < mutations_.size(); ++i) {
            const WeightedMutation& m = mutations_[i];
            if (!m.fixedRate || !(m.weight > 0) || !m.mutation->appliesTo(x)) continue;
            running += m.weight;
            if (u < running) return i;
        }
    }
    // The rest of [0, 1), rescaled (exactly u when no rate applies), to the weighted ones.
    double totalX = applicableWeight(x);
    if (!(totalX > 0) || !(rateX < 1)) return SIZE_MAX;
    double target = (rateX > 0 ? (u - rateX) / (1 - rateX) : u) * totalX;
    size_t chosen = SIZE_MAX;
    running = 0;
    for (size_t i = 0; i < mutations_.size(); ++i) {
        const WeightedMutation& m = mutations_[i];
        if (m.fixedRate || !(m.weight > 0) || !m.mutation->appliesTo(x)) continue;
        chosen = i;
        running += m.weight;
        if (target < running) break;
    }
    return chosen;
}

bool MarkovChain::proposeWithChoice(const MarkovPath& x, Rng& rng, MarkovPath& y, double& ratio,
                                    size_t& chosen) {
    float u = rng.nextFloat();
    chosen = choose(x, double(u));
    if (chosen == SIZE_MAX) return false;
    const WeightedMutation& m = mutations_[chosen];
    double densities = 0;
    if (!m.mutation->propose(x, rng, y, densities, rays_)) return false;
    if (restriction_ && !restriction_(y.type)) return false;
    // P(choice | y) / P(choice | x) (the header's): zero when the mutation does not apply to y
    // (no way back); 1 for a fixed rate.
    if (!m.mutation->appliesTo(y)) return false;
    if (m.fixedRate) {
        ratio = densities;
        return true;
    }
    double rateX = applicableRate(x), rateY = applicableRate(y);
    double totalX = applicableWeight(x), totalY = applicableWeight(y);
    ratio = densities * (totalX / totalY);
    if (rateX > 0 || rateY > 0) ratio *= (1 - rateY) / (1 - rateX);
    return true;
}

}  // namespace partita
