// Settings of the bidirectional path tracer beyond the job's RenderSettings, with defaults.
#pragma once

#include "integrators/sample_pass_settings.h"
#include "path/mis.h"

namespace partita {

/// The sample-pass loop's settings (target_error) are the only ones a job sets.
struct BdptSettings : SamplePassSettings {
    MisHeuristic heuristic = MisHeuristic::Power;
    int rouletteStartDepth = 3;  // as pt
    /// For tests: render only strategy (s, t) (-1: any), unweighted when `weighted` is false, so
    /// that each strategy's image can be checked alone (every strategy of a path length must
    /// converge to the same answer).
    int onlyS = -1, onlyT = -1;
    bool weighted = true;
};

}  // namespace partita
