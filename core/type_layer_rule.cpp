#include "type_layer_rule.h"

namespace partita {

bool needsTypeWeights(const RenderSettings& settings) {
    return !settings.everyTypeLayer && settings.maxTypeLayers > 0;
}

TypeLayers chooseTypeLayers(const RenderSettings& settings,
                            const std::map<PathType, double>& weights) {
    if (settings.everyTypeLayer) return TypeLayers::every();
    return TypeLayers::largest(weights, settings.maxTypeLayers);
}

}  // namespace partita
