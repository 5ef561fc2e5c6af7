// The settings of `mlt` with their defaults (Veach 1997, ch. 11; DESIGN.md), and the parameters
// a job sets them with (mltParameters(): bootstrap, chains, startup_share, direct, direct_spp,
// target_error).
#pragma once

#include <cstdint>
#include <string>

#include "mcmc/veach_mutations.h"
#include "params/settings_table.h"

namespace partita {

struct MltSettings {
    /// BDPT samples of the start-up (b and the initial paths); 0: by the start-up rule
    /// (mcmc/startup_rule.h: a mutation budget's mutations / 5 within [4096, 1e5], 1e5 for a
    /// time budget; Veach and Mitsuba use ~1e5). Parameter "bootstrap".
    uint64_t bootstrapSamples = 0;
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
    /// Samples per pixel of the per-pixel direct light; 0 (the default): chosen by the rule of
    /// direct_light.h (Neyman allocation from the measured variances and costs of the two
    /// parts: the direct light's first two samples per pixel, then its own samples so far, two
    /// halves of the chains), at least directMinSpp and at most directMaxSpp. A mutation budget's
    /// chains keep their mutations and the direct light comes after them, its cost counted in rays
    /// (deterministic); a time budget's chains run a first quarter of the time, then the rule
    /// splits the whole time in seconds. A fixed count (Mitsuba's directSamples is 16) with a
    /// mutation budget is rendered besides the mutations; with a time budget it stops early when it
    /// has had directShare of the time the bootstrap left, and the chains get the rest. Parameter
    /// "direct_spp".
    uint64_t directSpp = 0;
    /// The rule's fewest samples per pixel (Mitsuba's directSamples default): its variance is
    /// measured from the samples so far (pooledDirectVariance), and what is bright and rare
    /// (pool's glints: ~1 hit in 4 passes over the image) is seen only after enough of them.
    uint64_t directMinSpp = 16;
    uint64_t directMaxSpp = 4096;
    double directShare = 0.5;
    double firstChainShare = 0.25;  // auto with a time budget: the chains' measuring stage
    /// Stop once the render's own estimate of the combined image's relative RMSE is at or
    /// below this (mcmc/chain_error_monitor.h: two halves of the chains, b's error, the direct
    /// light's own halves); 0: never. With a mutation budget the chains and the direct light
    /// after them each get half of its square. Parameter "target_error".
    double targetError = 0;
    VeachMutationSettings mutations;
};

const SettingsTable<MltSettings>& mltParameters();

}  // namespace partita
