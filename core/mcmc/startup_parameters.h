// The parameters of an MCMC method's start-up that mlt, partitioned and guided all take, declared
// once: the start-up's sample count ("bootstrap") and the number of chains ("chains").
#pragma once

#include <string>

#include "params/parameter.h"

namespace partita {

/// "bootstrap": samples of the start-up (mlt's BDPT bootstrap, the partitioned methods'
/// pre-pass); `help` says what they estimate for the algorithm.
inline ParameterSpec bootstrapParameter(std::string help) {
    return ParameterSpec("bootstrap", std::move(help))
        .withUnit("samples")
        .within(1, double(uint64_t(1) << 40));
}

/// "chains": the Markov chains of the render, fewer when the budget would give a chain too few
/// mutations; a fixed number, so that the image does not depend on the thread count.
inline ParameterSpec chainsParameter() {
    return ParameterSpec("chains",
                         "Markov chains (fewer when the budget is small; never the thread count)")
        .within(1, 65536);
}

}  // namespace partita
