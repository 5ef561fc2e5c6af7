#include "mcmc/markov_chain.h"

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
        if (m.weight > 0 && m.mutation->appliesTo(p)) total += m.weight;
    return total;
}

bool MarkovChain::proposeWithChoice(const MarkovPath& x, Rng& rng, MarkovPath& y, double& ratio,
                                    size_t& chosen) {
    double totalX = applicableWeight(x);
    float u = rng.nextFloat();
    if (!(totalX > 0)) return false;
    // The mutation whose share of the applicable weight covers u.
    double target = double(u) * totalX, running = 0;
    for (size_t i = 0; i < mutations_.size(); ++i) {
        const WeightedMutation& m = mutations_[i];
        if (!(m.weight > 0) || !m.mutation->appliesTo(x)) continue;
        chosen = i;
        running += m.weight;
        if (target < running) break;
    }
    Mutation& mutation = *mutations_[chosen].mutation;
    double densities = 0;
    if (!mutation.propose(x, rng, y, densities, rays_)) return false;
    if (restriction_ && !restriction_(y.type)) return false;
    // P(choice | y) / P(choice | x): zero when the mutation does not apply to y (no way back).
    if (!mutation.appliesTo(y)) return false;
    double totalY = applicableWeight(y);
    ratio = densities * (totalX / totalY);
    return true;
}

}  // namespace partita
