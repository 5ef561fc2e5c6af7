// What the quality harness (`partita-eval reference` and `quality`) shares: a scene loaded once
// for many renders, and one in-process render timed by the wall clock with a progress bar.
#pragma once

#include <memory>
#include <string>

#include "algorithm.h"
#include "render_settings.h"

namespace partita {
class RenderScene;
class ThreadPool;
}  // namespace partita

namespace partita::eval {

/// Loads a .gltf/.glb (warnings on stderr) and builds its acceleration structure.
/// The scene at `path`, lit by `environment` (the job's, if any).
std::unique_ptr<RenderScene> loadRenderScene(const std::string& path,
                                             const EnvironmentSettings& environment);

struct TimedRender {
    RenderResult result;
    double wallSeconds = 0;  // runRender from call to return: setup, passes and final resolve
};

/// Renders with `algorithm` on `pool`, no previews; a progress bar on stderr labelled `label`
/// unless `quiet`. Exceptions of runRender pass through. A render under a time budget that runs
/// past twice its budget plus 10 s is cancelled: a std::runtime_error that says so.
TimedRender renderTimed(const RenderScene& scene, const std::string& algorithm,
                        RenderSettings settings, ThreadPool& pool, bool quiet,
                        const std::string& label);

/// The budget in a short phrase for tables and messages: "16 spp", "32 mpp", "2.5 s".
std::string budgetText(const RenderSettings& settings);

}  // namespace partita::eval
