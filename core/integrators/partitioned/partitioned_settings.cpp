#include "integrators/partitioned/partitioned_settings.h"
#include "mcmc/mutation_parameters.h"

namespace partita {

const SettingsTable<PartitionedSettings>& partitionedParameters() {
    static const SettingsTable<PartitionedSettings> table = [] {
        SettingsTable<PartitionedSettings> t;
        addPipelineParameters(t);
        addMutationParameters(t);
        return t;
    }();
    return table;
}

}  // namespace partita
