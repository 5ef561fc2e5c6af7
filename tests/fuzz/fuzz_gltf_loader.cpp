// libFuzzer target for the glTF loader: every input is tried as a GLB and as JSON glTF, with no
// external resources available. The loader's contract is that malformed input only ever raises
// SceneLoadError; anything else (another exception, a sanitizer report, a hang, an allocation
// beyond -rss_limit_mb) is a bug.
#include <spdlog/spdlog.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "gltf/camera_select.h"
#include "gltf/gltf_loader.h"

namespace {

partita::GltfLoadLimits fuzzLimits() {
    // Small limits keep every run fast and far below libFuzzer's memory limit; the code paths
    // that enforce them are the same as with the defaults.
    partita::GltfLoadLimits limits;
    limits.maxFileBytes = uint64_t(1) << 22;
    limits.maxTriangles = 1 << 16;
    limits.maxTexturePixels = 1 << 16;
    limits.maxTotalTexturePixels = 1 << 20;
    limits.maxNodeDepth = 64;
    return limits;
}

void loadOnce(const std::vector<uint8_t>& bytes, bool isBinary) {
    static const partita::MemoryResolver noFiles({});
    static const partita::GltfLoadLimits limits = fuzzLimits();
    try {
        partita::SceneData scene = partita::loadGltfMemory(bytes, isBinary, noFiles, limits);
        partita::CameraDesc camera = partita::defaultCamera(scene);
        (void)camera;
        (void)partita::selectCamera(scene, "");
    } catch (const partita::SceneLoadError&) {
        // expected for malformed input
    }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    spdlog::set_level(spdlog::level::off);  // warnings are expected and would slow fuzzing
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::vector<uint8_t> bytes(data, data + size);
    loadOnce(bytes, true);
    loadOnce(bytes, false);
    return 0;
}
