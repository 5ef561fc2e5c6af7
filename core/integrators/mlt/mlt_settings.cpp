#include "integrators/mlt/mlt_settings.h"

#include "mcmc/startup_parameters.h"

namespace partita {

const SettingsTable<MltSettings>& mltParameters() {
    static const SettingsTable<MltSettings> table = [] {
        SettingsTable<MltSettings> t;
        t.add(bootstrapParameter("BDPT bootstrap samples: b and the chains' initial paths"),
              &MltSettings::bootstrapSamples);
        t.add(chainsParameter(), &MltSettings::chains);
        t.add(startupShareParameter(), &MltSettings::startupShare);
        return t;
    }();
    return table;
}

}  // namespace partita
