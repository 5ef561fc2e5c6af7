#include "renderer.h"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "camera.h"
#include "gltf/camera_select.h"
#include "params/job_parameters.h"
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
    const AlgorithmRegistry::Entry& entry = registeredAlgorithm(algorithm);
    if (std::string err = validateJob(entry, settings); !err.empty())
        throw std::invalid_argument(err);
    return {
        entry.factory(settings.parameters),
        Camera(resolveCamera(scene.data(), settings.cameraName), settings.width, settings.height)};
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
    m["partita:budget_kind"] = budgetKindName(s.budgetKind);
    m["partita:budget"] = str(s.budget);
    // Every declared parameter as it ran; an environment file by its name only (the path is
    // the server's or the user's own business).
    for (const JobParameter& p : jobParameters(registeredAlgorithm(algorithm), s)) {
        if (std::holds_alternative<std::monostate>(p.value)) continue;
        std::string text = formatParameter(*p.spec, p.value);
        if (p.spec->name == "environment") text = std::filesystem::path(text).filename().string();
        if (p.spec->name == "environment" && text.empty()) continue;
        m["partita:" + p.spec->name] = text;
    }
    for (const auto& [k, v] : stats.values) m["partita:stat:" + k] = str(v);
    for (const auto& [k, v] : stats.labels) m["partita:stat:" + k] = v;
    return m;
}

}  // namespace partita
