// Settings of the bidirectional path tracer beyond the job's RenderSettings, with defaults.
#pragma once

#include "path/mis.h"

namespace partita {

struct BdptSettings {
    MisHeuristic heuristic = MisHeuristic::Power;
    int rouletteStartDepth = 3;  // as pt
    /// For tests: render only strategy (s, t) (-1: any), unweighted when `weighted` is false, so
    /// that each strategy's image can be checked alone (every strategy of a path length must
    /// converge to the same answer).
    int onlyS = -1, onlyT = -1;
    bool weighted = true;
};

}  // namespace partita
