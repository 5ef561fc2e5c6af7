// libFuzzer target for chain plans (core/mcmc/chain_plan.h), which travel inside shard plans:
// deserializeChainPlan, then every chain's initial path rebuilt on the Cornell box
// (deserializePath), as a shard does before it runs the chain. The contract: bad input throws
// std::invalid_argument; anything else is a bug.
#include <spdlog/spdlog.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>

#include "camera.h"
#include "gltf/gltf_loader.h"
#include "mcmc/chain_plan.h"
#include "path/path.h"
#include "render_scene.h"
#include "renderer.h"

namespace {

struct Scene {
    partita::RenderScene scene;
    partita::Camera camera;
    explicit Scene(partita::SceneData data)
        : scene(std::move(data)), camera(partita::resolveCamera(scene.data(), ""), 32, 32) {}
};

const Scene& cornell() {
    static const Scene scene(partita::loadGltfFile(PARTITA_SCENES_DIR "/cornell/cornell.gltf"));
    return scene;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    spdlog::set_level(spdlog::level::off);
    cornell();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const Scene& s = cornell();
    try {
        partita::ChainPlan plan = partita::deserializeChainPlan({data, size});
        (void)plan.mutations();
        for (const partita::PlannedChain& chain : plan.chains) {
            try {
                (void)partita::deserializePath(s.scene, s.camera, chain.start);
            } catch (const std::invalid_argument&) {
            }
        }
    } catch (const std::invalid_argument&) {
    }
    return 0;
}
