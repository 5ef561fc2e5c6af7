// The parameters of an MCMC method's start-up that mlt, partitioned and guided all take, declared
// once: the start-up's sample count ("bootstrap"), the number of chains ("chains"), and the
// share of a time budget the start-up may take ("startup_share"), with the rule it sets.
#pragma once

#include <algorithm>
#include <string>

#include "clock.h"
#include "params/parameter.h"
#include "render_settings.h"

namespace partita {

/// "bootstrap": samples of the start-up (mlt's BDPT bootstrap, the partitioned methods'
/// pre-pass); `help` says what they estimate for the algorithm. 0 (the default): as many as
/// the start-up rule gives the job's pixels and budget (startup_rule.h).
inline ParameterSpec bootstrapParameter(std::string help) {
    return ParameterSpec("bootstrap", std::move(help) + " (0: by the pixels and the budget)")
        .withUnit("samples")
        .within(0, double(uint64_t(1) << 40));
}

/// "chains": the Markov chains of the render, fewer when the budget would give a chain too few
/// mutations; a fixed number, so that the image does not depend on the thread count.
inline ParameterSpec chainsParameter() {
    return ParameterSpec("chains",
                         "Markov chains (fewer when the budget is small; never the thread count)")
        .within(1, 65536);
}

/// "startup_share": the largest share of a time budget that the start-up (bootstrap, pre-pass)
/// may take before the chains get the rest.
inline ParameterSpec startupShareParameter() {
    return ParameterSpec("startup_share",
                         "largest share of a time budget the start-up's samples may take")
        .above(0)
        .atMost(1);
}

/// When the start-up of a job begun at `start` stops taking samples: after `share` of a time
/// budget (at least its first wave of samples runs, sample_waves.h); never for a samples or
/// mutations budget, whose start-up always runs its `bootstrap` samples (issue #25 2: a
/// 1-second job spent hours in its pre-pass).
inline Deadline startupDeadline(const RenderSettings& s, Clock::time_point start, double share) {
    if (s.budgetKind != BudgetKind::Seconds) return kNoDeadline;
    double seconds = std::clamp(share, 0.0, 1.0) * s.budget;
    return start +
           std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

}  // namespace partita
