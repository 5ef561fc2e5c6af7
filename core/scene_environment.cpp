#include "scene_environment.h"

#include <memory>
#include <stdexcept>

#include "environment_map.h"
#include "image_io.h"
#include "render_scene.h"

namespace partita {

void attachEnvironment(SceneData& data, const EnvironmentSettings& env) {
    if (!env.enabled()) return;
    if (env.hasColor) {
        Rgb c(env.color[0], env.color[1], env.color[2]);
        data.environment = std::make_shared<EnvironmentMap>(EnvironmentMap::uniform(c));
        return;
    }
    Image image;
    try {
        // Its size is checked from the header, before it is decoded (issue #25 3).
        image = readExr(env.file, nullptr, size_t(kMaxEnvironmentPixels)).combined;
    } catch (const std::exception& e) {
        throw std::invalid_argument(std::string("environment: ") + e.what());
    }
    if (image.empty())
        throw std::invalid_argument("environment: the image has no R, G, B channels");
    data.environment = std::make_shared<EnvironmentMap>(std::move(image), env.rotationDegrees);
}

std::string darkSceneWarning(const RenderScene& scene) {
    if (scene.hasLights()) return {};
    return "the scene has no light and no environment, so it renders black (give an environment: "
           "--environment FILE or --environment-color R,G,B)";
}

}  // namespace partita
