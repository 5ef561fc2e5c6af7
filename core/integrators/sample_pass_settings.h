// The settings of the sample-pass loop that pt and bdpt share (sample_passes.h), and the
// parameters a job sets them with (samplePassParameters(): target_error).
#pragma once

#include "params/settings_table.h"

namespace partita {

struct SamplePassSettings {
    /// Stop once the render's own estimate of the combined image's relative RMSE
    /// (half_split_error.h) is at or below this, before the budget is spent; 0: never. The
    /// estimate is trusted from kMinHalfSamples samples per pixel in each half. Parameter
    /// "target_error".
    double targetError = 0;
    static constexpr uint64_t kMinHalfSamples = 4;
};

const SettingsTable<SamplePassSettings>& samplePassParameters();

}  // namespace partita
