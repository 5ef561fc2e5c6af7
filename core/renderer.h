// One in-process render from start to finish: choose the camera, look up the algorithm by name,
// run it on the pool. Front ends (partita-local, partitad, partita-eval) all go through here.
#pragma once

#include <atomic>
#include <filesystem>
#include <map>
#include <string>

#include <memory>

#include "algorithm.h"
#include "camera.h"
#include "render_settings.h"
#include "scene_data.h"

namespace partita {

class RenderScene;
class ThreadPool;

/// The camera named `name` (empty: the first one, or a default framing the scene when the file
/// has none). Throws std::invalid_argument naming the available cameras for an unknown name.
CameraDesc resolveCamera(const SceneData& scene, const std::string& name);

/// What a render needs before it runs: the algorithm's instance (looked up by name) and the
/// camera of the settings. Throws std::invalid_argument for an unknown algorithm or invalid
/// settings. runRender and the sharded render (shard/sharded_render.h) both start here.
struct PreparedRender {
    std::unique_ptr<Algorithm> algorithm;
    Camera camera;
};
PreparedRender prepareRender(const RenderScene& scene, const std::string& algorithm,
                             const RenderSettings& settings);

/// Runs `algorithm` (a registered name). Throws std::invalid_argument for an unknown algorithm
/// or invalid settings, RenderCancelled when cancelled.
RenderResult runRender(const RenderScene& scene, const std::string& algorithm,
                       const RenderSettings& settings, ThreadPool& pool,
                       const std::atomic<bool>& cancel, RenderObserver& observer);

/// Every setting and statistic as strings, for EXR attributes and JSON metadata.
std::map<std::string, std::string> describeRender(const std::string& algorithm,
                                                  const RenderSettings& settings,
                                                  const RenderStats& stats);

}  // namespace partita
