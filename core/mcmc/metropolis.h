// The Metropolis-Hastings step (paper Eq. 3), written once for every state space: the path
// space of the MCMC integrators and the small discrete spaces of the tests, which check that
// the step satisfies detailed balance exactly.
//
// From state x with target value f(x) > 0, a proposal y with f(y) and the ratio
// T(y->x) / T(x->y) of proposal densities is accepted with
//     a(x -> y) = min(1, f(y) T(y->x) / (f(x) T(x->y))).
// Expected-value splatting (Veach 1997, ch. 11): both states contribute to the estimate, y with
// weight a and x with weight 1 - a, whatever the random choice; this is unbiased and removes
// the variance of the accept/reject coin from the image.
//
// Rules the MCMC literature's bug trackers taught (DESIGN.md): a proposal with f(y) = 0, a
// non-finite ratio or no proposal at all is a rejection, never a division; there is no forced
// acceptance after many rejections (it breaks detailed balance).
#pragma once

#include <algorithm>
#include <cmath>

#include "rng.h"

namespace partita {

/// a(x -> y) of Eq. 3; 0 for an invalid proposal (see above).
inline double acceptanceProbability(double fCurrent, double fProposed, double reverseOverForward) {
    if (!(fProposed > 0) || !(reverseOverForward > 0) || !std::isfinite(fProposed) ||
        !std::isfinite(reverseOverForward))
        return 0;
    if (!(fCurrent > 0)) return 1;  // a chain never sits where f = 0; leave such a state
    double ratio = fProposed * reverseOverForward / fCurrent;
    return std::isfinite(ratio) ? std::min(1.0, ratio) : 1.0;
}

/// A proposal: the new state, its target value and T(y->x) / T(x->y); `valid` false when the
/// mutation produced nothing.
template <typename State>
struct Proposal {
    bool valid = false;
    State state{};
    double f = 0;
    double reverseOverForward = 0;
};

/// One step of the chain at (x, fx): proposes with `propose(x, rng) -> Proposal<State>`,
/// splats both states with `splat(state, weight)` (expected values; weights summing to 1; a
/// weight of 0 is not splatted), then moves to y with probability a. Returns a; `moved`, when
/// given, says whether the chain moved.
template <typename State, typename Propose, typename Splat>
double metropolisStep(State& x, double& fx, Rng& rng, Propose&& propose, Splat&& splat,
                      bool* moved = nullptr) {
    Proposal<State> y = propose(static_cast<const State&>(x), rng);
    double a = y.valid ? acceptanceProbability(fx, y.f, y.reverseOverForward) : 0;
    if (a > 0) splat(static_cast<const State&>(y.state), a);
    if (a < 1) splat(static_cast<const State&>(x), 1 - a);
    // One uniform per step whatever a is, so that a chain's random stream does not depend on
    // the acceptances before it.
    float u = rng.nextFloat();
    bool accept = a > 0 && double(u) < a;
    if (accept) {
        x = std::move(y.state);
        fx = y.f;
    }
    if (moved) *moved = accept;
    return a;
}

}  // namespace partita
