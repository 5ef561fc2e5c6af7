// The settings of `mlt` with their defaults (Veach 1997, ch. 11; DESIGN.md), and the parameters
// a job sets them with (mltParameters(): bootstrap, chains).
#pragma once

#include <cstdint>

#include "mcmc/veach_mutations.h"
#include "params/settings_table.h"

namespace partita {

struct MltSettings {
    /// BDPT samples of the start-up (b and the initial paths); Veach and Mitsuba use ~1e5.
    /// Parameter "bootstrap".
    uint64_t bootstrapSamples = 100000;
    /// With a time budget the bootstrap stops after this share of it (parameter
    /// "startup_share"; mcmc/startup_parameters.h).
    double startupShare = 0.1;
    /// Chains: a fixed number (never the thread count, so images do not depend on it), fewer
    /// when the budget would give a chain less than minMutationsPerChain. Parameter "chains".
    int chains = 256;
    uint64_t minMutationsPerChain = 32;
    /// Mutations per chain between two merges into the film (bounds the splat buffers).
    uint64_t roundMutations = 1024;
    VeachMutationSettings mutations;
};

const SettingsTable<MltSettings>& mltParameters();

}  // namespace partita
