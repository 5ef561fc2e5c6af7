#include "integrators/sample_pass_settings.h"

#include "target_error.h"

namespace partita {

const SettingsTable<SamplePassSettings>& samplePassParameters() {
    static const SettingsTable<SamplePassSettings> table = [] {
        SettingsTable<SamplePassSettings> t;
        t.add(targetErrorParameter("two interleaved halves of the samples"),
              &SamplePassSettings::targetError);
        return t;
    }();
    return table;
}

}  // namespace partita
