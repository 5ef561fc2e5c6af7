#include "integrators/sample_pass_settings.h"

namespace partita {

const SettingsTable<SamplePassSettings>& samplePassParameters() {
    static const SettingsTable<SamplePassSettings> table = [] {
        SettingsTable<SamplePassSettings> t;
        t.add(ParameterSpec("target_error",
                            "stop when the estimated relative RMSE of the combined image (from "
                            "two interleaved halves of the samples) is at or below this; the "
                            "budget is the most it may take (0: run the whole budget)")
                  .within(0, 1),
              &SamplePassSettings::targetError);
        return t;
    }();
    return table;
}

}  // namespace partita
