// Stopping at a target error (issue #26): the parameter every algorithm that estimates its own
// error declares ("target_error"), written once. pt and bdpt estimate from two interleaved
// halves of their samples (half_split_error.h, integrators/sample_passes.h); the MCMC methods
// from two halves of their chains with their normalising constants' and per-pixel parts' errors
// (mcmc/chain_error_monitor.h).
#pragma once

#include <string>

#include "params/parameter.h"

namespace partita {

/// "target_error": stop when the estimated relative RMSE of the combined image is at or below
/// it; `halves` says what the two halves are.
inline ParameterSpec targetErrorParameter(const std::string& halves) {
    return ParameterSpec("target_error",
                         "stop when the estimated relative RMSE of the combined image (from " +
                             halves +
                             ") is at or below this; the budget is the most it may take (0: run "
                             "the whole budget)")
        .within(0, 1);
}

}  // namespace partita
