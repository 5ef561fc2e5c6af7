// What every mutation of the MCMC methods provides (Veach 1997, ch. 11): whether it applies to
// a path (a function of the path's structure alone), and a proposal y with the ratio of
// proposal densities T(y->x) / T(x->y). Densities are in the area measure of the vertices with
// Dirac vertices written as their branch coefficients and probabilities (dirac_vertex.h), so
// that f(y) T(y->x) / (f(x) T(x->y)) is exact. The chain (markov_chain.h) chooses among the
// mutations that apply and puts the probability of that choice into the ratio both ways.
//
// One file per mutation: bidirectional_mutation, lens_perturbation, caustic_perturbation,
// multi_chain_perturbation, independence_mutation, guide/guided_perturbation (paper Sec. 5).
#pragma once

#include <cstdint>
#include <string>

#include "mcmc/markov_path.h"
#include "rng.h"

namespace partita {

class Mutation {
  public:
    virtual ~Mutation() = default;
    virtual std::string name() const = 0;
    virtual bool appliesTo(const MarkovPath& x) const = 0;
    /// Proposes y from x (y evaluated: f, f*, type, raster). False when there is no proposal
    /// (the chain counts it as a rejection). `rays` counts the rays traced.
    virtual bool propose(const MarkovPath& x, Rng& rng, MarkovPath& y, double& reverseOverForward,
                         uint64_t& rays) = 0;
};

}  // namespace partita
