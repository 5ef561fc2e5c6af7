#include "integrators/mlt/mlt_settings.h"

#include "mcmc/mutation_parameters.h"
#include "mcmc/startup_parameters.h"
#include "target_error.h"

namespace partita {

const SettingsTable<MltSettings>& mltParameters() {
    static const SettingsTable<MltSettings> table = [] {
        SettingsTable<MltSettings> t;
        t.add(bootstrapParameter("BDPT bootstrap samples: b and the chains' initial paths"),
              &MltSettings::bootstrapSamples);
        t.add(chainsParameter(), &MltSettings::chains);
        t.add(startupShareParameter(), &MltSettings::startupShare);
        t.add(ParameterSpec("direct",
                            "direct light (L S* E, L D S* E): per-pixel samples apart from the "
                            "chains, or left to the chains")
                  .withChoices({"per-pixel", "chains"}),
              &MltSettings::direct);
        t.add(ParameterSpec("direct_spp",
                            "samples per pixel of the per-pixel direct light (0: chosen from the "
                            "measured variances and costs of it and the chains)")
                  .withUnit("samples")
                  .within(0, 1 << 20),
              &MltSettings::directSpp);
        t.add(targetErrorParameter("two halves of the chains, b's error and two halves of the "
                                   "direct light"),
              &MltSettings::targetError);
        addMutationParameters(t);
        return t;
    }();
    return table;
}

}  // namespace partita
