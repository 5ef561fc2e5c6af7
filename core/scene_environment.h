// Lighting a loaded scene with the job's environment, and the warning for a scene that has no
// light at all (it would render black, silently).
#pragma once

#include <string>

#include "render_settings.h"
#include "scene_data.h"

namespace partita {

class RenderScene;

/// Largest environment image accepted (pixels), against memory exhaustion by a request.
constexpr long long kMaxEnvironmentPixels = 16384LL * 8192LL;

/// Sets data.environment from `env` (nothing when !env.enabled()). The file is read as given:
/// a front end resolves and checks the path first. Throws std::invalid_argument with one line
/// for an unreadable, empty or oversized image.
void attachEnvironment(SceneData& data, const EnvironmentSettings& env);

/// "" when the scene has a light or an environment, else the one-line warning to show.
std::string darkSceneWarning(const RenderScene& scene);

}  // namespace partita
