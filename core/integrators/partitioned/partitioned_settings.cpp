#include "integrators/partitioned/partitioned_settings.h"

namespace partita {

const SettingsTable<PartitionedSettings>& partitionedParameters() {
    static const SettingsTable<PartitionedSettings> table = [] {
        SettingsTable<PartitionedSettings> t;
        addPipelineParameters(t);
        return t;
    }();
    return table;
}

}  // namespace partita
