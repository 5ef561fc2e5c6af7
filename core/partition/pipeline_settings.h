// The settings that `partitioned` and `guided` share (their pipeline, partitioned_pipeline.h),
// with their defaults, and the parameters a job sets them with: k, prepass, bootstrap, chains.
#pragma once

#include <cstdint>
#include <string>

#include "mcmc/startup_parameters.h"
#include "params/settings_table.h"
#include "target_error.h"

namespace partita {

struct PartitionPipelineSettings {
    int k = 10;  // K: the top-K path types become partitions, plus the complement (paper Sec. 4)
    /// What a partition is (partition.h): "types", one exact Heckbert string each (the
    /// paper's), or "classes", classes of types by run structure ("LS+DE"), split until K.
    std::string partitions = "types";
    /// The pre-pass estimator: "pt" (the paper's), "bdpt" or "auto" (bdpt when the scene has a
    /// delta light, else pt). Default bdpt, the estimator of mlt's start-up: at the same 100000
    /// samples its b_i are less noisy than the path tracer's (the sum of b_i spreads 3-4% over
    /// seeds with pt), and partitioned's RMSE at 32 mpp went from 0.99-1.33x mlt's to
    /// 0.84-0.98x on every shipped scene (docs/partitioned-study.md).
    std::string prepass = "bdpt";
    uint64_t bootstrapSamples =
        0;                      // the pre-pass's, 0: by the rule (mcmc/startup_rule.h), as mlt's
    double startupShare = 0.1;  // with a time budget, the pre-pass's share at most (as mlt's)
    uint64_t burnIn = 1024;  // per chain, before its first splat (the paper's), at most the rule's
    int chains = 256;        // over all partitions, in proportion to P(i)
    uint64_t minMutationsPerChain = 32;
    uint64_t roundMutations = 1024;
    uint64_t prepassMemoryBytes = uint64_t(256) << 20;  // half B's path records
    /// Each partition's estimator (effort_plan.h): "auto" (the lower expected error per second
    /// from the pilots), "chains" (the paper's) or "per-pixel" (restricted pt/BDPT for all).
    /// Default auto: at equal time it beats the paper's chains on cornell-glass, door-ajar,
    /// pool and bathroom (docs/partition-estimators.md, "At equal time").
    std::string estimators = "auto";
    /// The per-pixel partitions' estimator: "auto" (the path tracer in a scene without delta
    /// lights, else BDPT), "pilot" (both piloted, the plan of lower predicted error x cost),
    /// "pt" or "bdpt". Not "pilot" by default: its one-sample pilots cannot see what the path
    /// tracer's stratified samples gain, and chose BDPT on cornell-glass at 1.5x the path
    /// tracer's RMSE; on door-ajar, bathroom and pool it chose the path tracer anyway
    /// (docs/partition-estimators.md, "The per-pixel estimator").
    std::string pixelEstimator = "auto";
    /// The budget across partitions: "neyman" (by measured error per cost, effort_plan.h) or
    /// "p" (the paper's Eq. 10: mutations in proportion to P(i); every partition has chains).
    std::string allocation = "p";
    /// "per-pixel": with estimators other than "chains", the direct-light class (L S* E,
    /// L D S* E) is a partition of its own estimated per pixel, as mlt's `direct` default, and
    /// the other partitions hold the other types; "chains": it stays with the types.
    std::string direct = "per-pixel";
    /// The chains' pilot's share of the budget (of the mutations, or of the time left after the
    /// pre-pass).
    double pilotShare = 0.05;
    /// Stop once the render's own estimate of the combined image's relative RMSE is at or
    /// below this (partition_error.h); 0: never. Parameter "target_error".
    double targetError = 0;
};

/// Declares the pipeline's parameters in the table of S (PartitionedSettings, GuidedSettings).
template <class S>
void addPipelineParameters(SettingsTable<S>& t) {
    t.add(ParameterSpec("k",
                        "K: path types that become partitions of their own, besides the "
                        "complement")
              .withUnit("partitions")
              .within(0, 64),
          &PartitionPipelineSettings::k);
    t.add(ParameterSpec("partitions",
                        "what a partition is: types (one exact Heckbert string each, the "
                        "paper's) or classes (types of one run structure, such as LS+DE, the "
                        "largest split until there are K)")
              .withChoices({"types", "classes"}),
          &PartitionPipelineSettings::partitions);
    t.add(ParameterSpec("prepass",
                        "pre-pass estimator (auto: bdpt when the scene has a delta light, else pt)")
              .withChoices({"auto", "pt", "bdpt"}),
          &PartitionPipelineSettings::prepass);
    t.add(bootstrapParameter("pre-pass samples: the path types, P(i), b_i and the chains' starts"),
          &PartitionPipelineSettings::bootstrapSamples);
    t.add(chainsParameter(), &PartitionPipelineSettings::chains);
    t.add(startupShareParameter(), &PartitionPipelineSettings::startupShare);
    t.add(ParameterSpec("burn_in",
                        "burn-in steps of each chain before its first splat (at most a tenth of "
                        "the chain's mutations; with a time budget, of the chains' time)")
              .withUnit("steps")
              .within(0, 1 << 20),
          &PartitionPipelineSettings::burnIn);
    t.add(ParameterSpec("estimators",
                        "each partition's estimator: auto (chains or per-pixel BDPT samples, "
                        "whichever the pilots predict gives less error per cost), chains (the "
                        "paper's), per-pixel (BDPT restricted to the partition, for all)")
              .withChoices({"auto", "chains", "per-pixel"}),
          &PartitionPipelineSettings::estimators);
    t.add(ParameterSpec("pixel_estimator",
                        "the per-pixel partitions' samples: auto (the path tracer's in a scene "
                        "without delta lights, else BDPT's), pilot (both piloted, the one "
                        "predicted to give less error per cost), pt (not in a scene with a delta "
                        "light) or bdpt")
              .withChoices({"auto", "pilot", "pt", "bdpt"}),
          &PartitionPipelineSettings::pixelEstimator);
    t.add(ParameterSpec("allocation",
                        "the budget across partitions: neyman (by the pilots' error per cost) or "
                        "p (Eq. 10, mutations in proportion to P(i); with estimators=chains only, "
                        "other estimators always use neyman)")
              .withChoices({"neyman", "p"}),
          &PartitionPipelineSettings::allocation);
    t.add(ParameterSpec("direct",
                        "with estimators auto or per-pixel: per-pixel (the direct light, L S* E "
                        "and L D S* E, is a partition of its own, always estimated per pixel, as "
                        "mlt does) or chains (it stays with the other types); estimators=chains "
                        "leaves it with them")
              .withChoices({"per-pixel", "chains"}),
          &PartitionPipelineSettings::direct);
    t.add(ParameterSpec("pilot_share",
                        "the chains' pilot's share of the budget (mutations, at most 4 per "
                        "pixel, or the time after the pre-pass); its chains are not part of the "
                        "image")
              .within(0.001, 0.5),
          &PartitionPipelineSettings::pilotShare);
    t.add(targetErrorParameter("each partition's: two halves of its chains and its b's error, "
                               "or its per-pixel pilot's variance"),
          &PartitionPipelineSettings::targetError);
}

}  // namespace partita
