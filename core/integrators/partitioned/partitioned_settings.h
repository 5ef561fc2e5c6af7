// The settings of `partitioned` with their defaults (paper Sec. 4; DESIGN.md), and the
// parameters a job sets them with (partitionedParameters(): the pipeline's k, prepass,
// bootstrap, chains).
#pragma once

#include "mcmc/veach_mutations.h"
#include "params/settings_table.h"
#include "partition/pipeline_settings.h"

namespace partita {

struct PartitionedSettings : PartitionPipelineSettings {
    /// Veach's mutations, unchanged. Chains of a one-type partition try only bidirectional
    /// mutations that keep the path's length (a different length is another type).
    VeachMutationSettings mutations;
};

const SettingsTable<PartitionedSettings>& partitionedParameters();

}  // namespace partita
