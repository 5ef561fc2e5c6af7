// The runtime camera: turns raster positions (pixels, (0,0) at the top-left corner of the image)
// into primary rays, and world points back into raster positions (needed by light tracing and
// by the guided image-plane proposal).
#pragma once

#include <optional>

#include "math/vec.h"
#include "ray.h"
#include "scene_data.h"

namespace partita {

class Camera {
  public:
    Camera(const CameraDesc& desc, int width, int height);

    int width() const { return width_; }
    int height() const { return height_; }
    bool isOrthographic() const { return orthographic_; }
    Vec3f position() const { return origin_; }
    /// Unit view direction (the camera's -Z in world space).
    Vec3f forward() const { return forward_; }

    /// Primary ray through the raster position (continuous pixel coordinates).
    Ray generateRay(Vec2f raster) const;

    /// Raster position of world point p, or nullopt when it is behind the camera or off the image.
    std::optional<Vec2f> rasterFromWorld(Vec3f p) const;

    /// Area of one pixel on the image plane at distance 1 (perspective) or in world units
    /// (orthographic): the Jacobian between raster and image-plane measure.
    float pixelArea() const { return pixelWidth_ * pixelHeight_; }

  private:
    bool orthographic_ = false;
    int width_, height_;
    Vec3f origin_, right_, up_, forward_;  // world-space orthonormal basis
    float pixelWidth_, pixelHeight_;       // image-plane size of one pixel
    float halfWidth_, halfHeight_;         // image-plane half extents
};

}  // namespace partita
