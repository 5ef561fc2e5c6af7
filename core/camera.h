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

    /// The same view and image plane seen through a `width` x `height` raster (a downscaled
    /// survey of the image; pixels are square when the aspect ratio matches).
    Camera resized(int width, int height) const;

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
    /// Area of the whole image on that plane: A = width * height * pixelArea().
    float imagePlaneArea() const { return pixelArea() * float(width_) * float(height_); }

    // Importance (for bidirectional methods). Only a perspective pinhole can be reached by a
    // connection from the scene (light tracing); an orthographic camera's rays are parallel, a
    // Dirac delta in direction, so nothing connects to it.
    //
    // The pinhole's importance is normalised over the image plane at distance 1 (pbrt's
    // convention): We(w) = 1 / (A cos^4 theta), whose direction density is
    // pdf(w) = 1 / (A cos^3 theta), so a camera ray's weight We cos / pdf is exactly 1. Its
    // support is the image extended by half a pixel on every side: the tent filter of a border
    // pixel (centre 0.5, radius 1) reaches raster -0.5, and the camera rays of the path tracer
    // go there too, so a light-tracing splat must be able to land there as well.
    bool isConnectable() const { return !orthographic_; }
    /// Raster position of world point p (not clipped to the image), or nullopt behind the camera.
    std::optional<Vec2f> rasterOf(Vec3f p) const;
    /// Whether raster position r lies in the importance's support (see above).
    bool inImportanceSupport(Vec2f r) const;
    /// We for the unit direction w leaving the pinhole; 0 outside the support. Perspective only.
    float importance(Vec3f w) const;
    /// The solid-angle density of camera rays in direction w, normalised over the whole image
    /// (the density every pixel's tent-filtered rays add up to, divided by the pixel count); 0
    /// outside the support. For an orthographic camera, the area density 1 / A on its plane.
    float directionPdf(Vec3f w) const;

  private:
    bool orthographic_ = false;
    int width_, height_;
    Vec3f origin_, right_, up_, forward_;  // world-space orthonormal basis
    float pixelWidth_, pixelHeight_;       // image-plane size of one pixel
    float halfWidth_, halfHeight_;         // image-plane half extents
};

}  // namespace partita
