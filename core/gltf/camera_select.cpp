#include "gltf/camera_select.h"

#include <fmt/format.h>

#include <cmath>

#include "gltf/gltf_loader.h"

namespace partita {

int selectCamera(const SceneData& scene, const std::string& name) {
    if (name.empty()) return scene.cameras.empty() ? -1 : 0;
    for (size_t i = 0; i < scene.cameras.size(); ++i)
        if (scene.cameras[i].name == name) return int(i);
    std::string available;
    for (const CameraDesc& cam : scene.cameras) {
        if (!available.empty()) available += ", ";
        available += fmt::format("'{}'", printableUri(cam.name));
    }
    if (available.empty()) available = "none (the scene has no cameras)";
    throw SceneLoadError(
        fmt::format("unknown camera '{}'; available: {}", printableUri(name), available));
}

CameraDesc defaultCamera(const SceneData& scene) {
    CameraDesc cam;
    cam.name = "default";
    cam.type = CameraDesc::Type::Perspective;
    cam.yfov = 0.8f;
    Bounds3f bounds = scene.bounds();
    Vec3f center(0.f), eye(0, 0, 1);
    if (!bounds.empty()) {
        center = bounds.center();
        float radius = std::max(0.5f * length(bounds.diagonal()), 1e-3f);
        // The bounding sphere touches the top and bottom of the view at this distance; a little
        // margin keeps it off the frame edge.
        float distance = 1.1f * radius / std::sin(0.5f * cam.yfov);
        eye = center + Vec3f(0, 0, distance);
        cam.znear = 0.5f * std::max(1e-4f * distance, distance - radius);
    }
    cam.cameraToWorld = Mat4::translation(eye);  // identity rotation: looking down -Z
    return cam;
}

}  // namespace partita
