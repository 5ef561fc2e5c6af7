#include "camera.h"

#include <cmath>

namespace partita {

Camera::Camera(const CameraDesc& desc, int width, int height)
    : orthographic_(desc.type == CameraDesc::Type::Orthographic), width_(width), height_(height) {
    origin_ = desc.cameraToWorld.transformPoint({0, 0, 0});
    // glTF cameras must not scale; normalise anyway so a sloppy file still renders.
    right_ = normalize(desc.cameraToWorld.transformVector({1, 0, 0}));
    up_ = normalize(desc.cameraToWorld.transformVector({0, 1, 0}));
    forward_ = normalize(desc.cameraToWorld.transformVector({0, 0, -1}));
    // The image's own aspect ratio wins over the file's hint, so pixels stay square.
    float aspect = float(width) / float(height);
    if (orthographic_) {
        halfHeight_ = desc.ymag;
    } else {
        halfHeight_ = std::tan(0.5f * desc.yfov);
    }
    halfWidth_ = halfHeight_ * aspect;
    pixelWidth_ = 2 * halfWidth_ / float(width);
    pixelHeight_ = 2 * halfHeight_ / float(height);
}

Camera Camera::resized(int width, int height) const {
    Camera c = *this;
    c.width_ = width;
    c.height_ = height;
    c.pixelWidth_ = 2 * halfWidth_ / float(width);
    c.pixelHeight_ = 2 * halfHeight_ / float(height);
    return c;
}

Ray Camera::generateRay(Vec2f raster) const {
    float x = -halfWidth_ + raster.x * pixelWidth_;
    float y = halfHeight_ - raster.y * pixelHeight_;
    if (orthographic_) return {origin_ + right_ * x + up_ * y, forward_, kInf};
    return {origin_, normalize(right_ * x + up_ * y + forward_), kInf};
}

std::optional<Vec2f> Camera::rasterFromWorld(Vec3f p) const {
    std::optional<Vec2f> r = rasterOf(p);
    if (!r) return std::nullopt;
    Vec2f raster = *r;
    if (!(raster.x >= 0 && raster.x < float(width_) && raster.y >= 0 && raster.y < float(height_)))
        return std::nullopt;
    return raster;
}

std::optional<Vec2f> Camera::rasterOf(Vec3f p) const {
    Vec3f d = p - origin_;
    float z = dot(d, forward_);
    float x = dot(d, right_), y = dot(d, up_);
    if (!orthographic_) {
        if (z <= 0) return std::nullopt;
        x /= z;
        y /= z;
    }
    return Vec2f{(x + halfWidth_) / pixelWidth_, (halfHeight_ - y) / pixelHeight_};
}

bool Camera::inImportanceSupport(Vec2f r) const {
    return r.x >= -0.5f && r.x < float(width_) + 0.5f && r.y >= -0.5f &&
           r.y < float(height_) + 0.5f;
}

float Camera::importance(Vec3f w) const {
    if (orthographic_) return 0;
    float cosTheta = dot(w, forward_);
    if (cosTheta <= 0) return 0;
    std::optional<Vec2f> r = rasterOf(origin_ + w);
    if (!r || !inImportanceSupport(*r)) return 0;
    float cos2 = cosTheta * cosTheta;
    return 1 / (imagePlaneArea() * cos2 * cos2);
}

float Camera::directionPdf(Vec3f w) const {
    if (orthographic_) return 1 / imagePlaneArea();
    float cosTheta = dot(w, forward_);
    if (cosTheta <= 0) return 0;
    std::optional<Vec2f> r = rasterOf(origin_ + w);
    if (!r || !inImportanceSupport(*r)) return 0;
    return 1 / (imagePlaneArea() * cosTheta * cosTheta * cosTheta);
}

}  // namespace partita
