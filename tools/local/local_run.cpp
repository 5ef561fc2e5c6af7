#include "local_run.h"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <stdexcept>

#include "gltf/gltf_loader.h"
#include "scene_environment.h"

namespace partita {

RenderScene loadLocalScene(const std::string& path, const EnvironmentSettings& environment) {
    SceneData data = loadGltfFile(path);
    for (const auto& w : data.warnings) spdlog::warn("{}", w);
    attachEnvironment(data, environment);
    return RenderScene(std::move(data));
}

}  // namespace partita
