// How a render chooses the path types its films keep apart (issue #24): the rule in one place.
//
// Before the main render, the algorithm measures a weight per type deterministically: pt and
// bdpt run a short survey (integrators/layer_survey.h), the MCMC algorithms sum their bootstrap
// candidates' weights. The `layers` largest (ties by PathType order) are kept; every other type
// sums into "other". Partition films keep none (their images are combined ones).
#pragma once

#include <map>

#include "path_type.h"
#include "render_settings.h"
#include "type_layers.h"

namespace partita {

/// Whether `settings` need per-type weights to choose their layers (not when every type is
/// kept, nor when none is).
bool needsTypeWeights(const RenderSettings& settings);

/// every() when settings.everyTypeLayer; else the settings.maxTypeLayers types of largest
/// weight (none for 0).
TypeLayers chooseTypeLayers(const RenderSettings& settings,
                            const std::map<PathType, double>& weights);

}  // namespace partita
