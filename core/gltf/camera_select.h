// Choosing the camera a render uses: one of the scene's cameras by name, or a default framing of
// the scene when the file has none.
#pragma once

#include <string>

#include "scene_data.h"

namespace partita {

/// Index into scene.cameras of the camera called `name`; an empty name picks the first camera.
/// Returns -1 when `name` is empty and the scene has no camera. An unknown name throws
/// SceneLoadError listing the available names.
int selectCamera(const SceneData& scene, const std::string& name);

/// A perspective camera on the +Z side of the scene's bounds, looking down -Z (+Y up) at their
/// centre, far enough back that the bounding sphere fits the vertical field of view.
CameraDesc defaultCamera(const SceneData& scene);

}  // namespace partita
