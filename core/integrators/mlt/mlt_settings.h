// The settings of `mlt` with their defaults (Veach 1997, ch. 11; DESIGN.md), and the parameters
// a job sets them with (mltParameters(): bootstrap, chains, startup_share, direct, direct_spp).
#pragma once

#include <cstdint>
#include <string>

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
    /// Where the direct-light paths (L S* E, L D S* E) go (issue #22 1, direct_light.h):
    /// "per-pixel", a per-pixel estimator of its own with the chains restricted to every other
    /// path (as Veach & Guibas and Mitsuba's mlt), or "chains", every path to the chains (the
    /// behaviour before; the same image bit for bit). Parameter "direct".
    std::string direct = "per-pixel";
    /// Samples per pixel of the per-pixel direct light: Mitsuba's `directSamples` default. A
    /// mutation budget gets them besides its mutations (deterministic: the image depends on
    /// neither threads nor timing); a time budget runs them after the bootstrap, stopping early
    /// when they would take more than directShare of the time left, and the chains get the rest.
    /// Parameter "direct_spp".
    uint64_t directSpp = 16;
    double directShare = 0.5;
    VeachMutationSettings mutations;
};

const SettingsTable<MltSettings>& mltParameters();

}  // namespace partita
