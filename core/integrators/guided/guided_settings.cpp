#include "integrators/guided/guided_settings.h"
#include "mcmc/mutation_parameters.h"

namespace partita {

const SettingsTable<GuidedSettings>& guidedParameters() {
    static const SettingsTable<GuidedSettings> table = [] {
        SettingsTable<GuidedSettings> t;
        addPipelineParameters(t);
        addMutationParameters(t);
        t.add(ParameterSpec("y", "|Y'|: candidate pixels of each guided step (paper Sec. 5)")
                  .withUnit("pixels")
                  .within(1, 4096),
              &GuidedSettings::y);
        t.add(ParameterSpec("radius", "R: radius of the candidates' disk (paper Eq. 18)")
                  .withUnit("pixels")
                  .above(0)
                  .atMost(4096),
              &GuidedSettings::radius);
        t.add(
            ParameterSpec("epsilon",
                          "epsilon of Eq. 17: V' below it, relative to the partition image's mean")
                .above(0)
                .atMost(1),
            &GuidedSettings::epsilon);
        t.add(ParameterSpec("move",
                            "each partition's image-plane move: guided (the paper's), lens (the "
                            "lens perturbation, as partitioned) or auto (the chains' pilot runs "
                            "both, each partition keeps the one of less error per cost)")
                  .withChoices({"auto", "guided", "lens"}),
              &GuidedSettings::move);
        t.add(ParameterSpec("through_specular",
                            "the guided move also for paths whose camera ray meets specular "
                            "surfaces before their first non-specular vertex (the paper's); "
                            "false: the lens perturbation for those, whose guide the G-buffer's "
                            "one specular branch per pixel may not describe"),
              &GuidedSettings::throughSpecular);
        return t;
    }();
    return table;
}

}  // namespace partita
