#include "renderer.h"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "camera.h"
#include "gltf/camera_select.h"
#include "render_scene.h"
#include "scene_environment.h"
#include "thread_pool.h"

namespace partita {

CameraDesc resolveCamera(const SceneData& scene, const std::string& name) {
    if (scene.cameras.empty() && name.empty()) return defaultCamera(scene);
    int index = selectCamera(scene, name);
    if (index < 0) {
        std::string names;
        for (const auto& c : scene.cameras)
            names += (names.empty() ? "" : ", ") + ("'" + c.name + "'");
        throw std::invalid_argument("no camera named '" + name + "' (the scene has: " +
                                    (names.empty() ? std::string("none") : names) + ")");
    }
    return scene.cameras[size_t(index)];
}

PreparedRender prepareRender(const RenderScene& scene, const std::string& algorithm,
                             const RenderSettings& settings) {
    registerBuiltinAlgorithms();
    const auto* entry = AlgorithmRegistry::instance().find(algorithm);
    if (!entry) throw std::invalid_argument("unknown algorithm '" + algorithm + "'");
    if (std::string err = validateSettings(settings); !err.empty())
        throw std::invalid_argument(err);
    return {entry->factory(), Camera(resolveCamera(scene.data(), settings.cameraName),
                                     settings.width, settings.height)};
}

RenderResult runRender(const RenderScene& scene, const std::string& algorithm,
                       const RenderSettings& settings, ThreadPool& pool,
                       const std::atomic<bool>& cancel, RenderObserver& observer) {
    PreparedRender prepared = prepareRender(scene, algorithm, settings);
    const Camera& camera = prepared.camera;
    auto& instance = prepared.algorithm;
    RenderContext ctx{scene, camera, settings, pool, cancel, observer};
    std::string dark = darkSceneWarning(scene);
    if (!dark.empty()) spdlog::warn("{}", dark);
    RenderResult result = instance->render(ctx);
    if (!dark.empty()) result.stats.labels["warning"] = dark;
    return result;
}

std::map<std::string, std::string> describeRender(const std::string& algorithm,
                                                  const RenderSettings& s,
                                                  const RenderStats& stats) {
    auto str = [](auto v) {
        std::ostringstream o;
        o << v;
        return o.str();
    };
    std::map<std::string, std::string> m;
    m["partita:algorithm"] = algorithm;
    m["partita:width"] = str(s.width);
    m["partita:height"] = str(s.height);
    m["partita:camera"] = s.cameraName;
    m["partita:budget_kind"] = s.budgetKind == BudgetKind::SamplesPerPixel     ? "spp"
                               : s.budgetKind == BudgetKind::MutationsPerPixel ? "mpp"
                                                                               : "seconds";
    m["partita:budget"] = str(s.budget);
    m["partita:seed"] = str(s.seed);
    m["partita:max_depth"] = str(s.maxDepth);
    m["partita:k"] = str(s.partitions);
    m["partita:y"] = str(s.guideCandidates);
    m["partita:radius"] = str(s.guideRadius);
    m["partita:epsilon"] = str(s.guideEpsilon);
    if (s.bootstrapSamples > 0) m["partita:bootstrap"] = str(s.bootstrapSamples);
    m["partita:prepass"] = s.prepass;
    const EnvironmentSettings& env = s.environment;
    if (env.enabled()) {
        m["partita:environment"] =
            env.hasColor ? str(env.color[0]) + "," + str(env.color[1]) + "," + str(env.color[2])
                         : std::filesystem::path(env.file).filename().string();
        m["partita:environment_rotation"] = str(env.rotationDegrees);
    }
    for (const auto& [k, v] : stats.values) m["partita:stat:" + k] = str(v);
    for (const auto& [k, v] : stats.labels) m["partita:stat:" + k] = v;
    return m;
}

}  // namespace partita
