#include "scene_data.h"

namespace partita {

Bounds3f SceneData::bounds() const {
    Bounds3f b;
    for (const auto& m : meshes)
        for (const auto& p : m.positions) b.expand(p);
    return b;
}

}  // namespace partita
