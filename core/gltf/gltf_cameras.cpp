#include "gltf/gltf_cameras.h"

#include <cmath>

#include "gltf/gltf_common.h"

namespace partita::gltf {

namespace {

Vec3f column(const Mat4& m, int c) { return {m.m[c][0], m.m[c][1], m.m[c][2]}; }

void setColumn(Mat4& m, int c, Vec3f v) {
    m.m[c][0] = v.x;
    m.m[c][1] = v.y;
    m.m[c][2] = v.z;
}

std::optional<Vec3f> unit(Vec3f v) {
    float len = length(v);
    if (!std::isfinite(len) || !(len > 1e-20f)) return std::nullopt;
    return v / len;
}

bool hasScale(const Mat4& m) {
    for (int c = 0; c < 3; ++c)
        if (std::fabs(length(column(m, c)) - 1.f) > 1e-3f) return true;
    return false;
}

void fillPerspective(LoadContext& ctx, const tinygltf::PerspectiveCamera& p, int index,
                     CameraDesc& cam) {
    if (!(p.yfov > 0 && p.yfov < kPi))
        failf("camera {}: perspective yfov {} is not in (0, pi)", index, p.yfov);
    cam.type = CameraDesc::Type::Perspective;
    cam.yfov = float(p.yfov);
    if (p.aspectRatio > 0 && p.aspectRatio < 1e6)
        cam.aspectRatio = float(p.aspectRatio);
    else if (p.aspectRatio != 0)
        ctx.warn(fmt::format("camera {}: aspectRatio {} is invalid; using the image's", index,
                             p.aspectRatio));
    cam.znear = clampedFloat(p.znear, 0, 1e30f, 0);
}

void fillOrthographic(const tinygltf::OrthographicCamera& o, int index, CameraDesc& cam) {
    if (!std::isfinite(o.xmag) || !std::isfinite(o.ymag) || o.xmag == 0 || o.ymag == 0)
        failf("camera {}: orthographic xmag/ymag must be finite and non-zero", index);
    cam.type = CameraDesc::Type::Orthographic;
    cam.xmag = std::fabs(toFloat(o.xmag));
    cam.ymag = std::fabs(toFloat(o.ymag));
    cam.znear = clampedFloat(o.znear, 0, 1e30f, 0);
}

}  // namespace

std::optional<Mat4> orthonormalized(const Mat4& m) {
    std::optional<Vec3f> z = unit(column(m, 2));
    if (!z) return std::nullopt;
    Vec3f y = column(m, 1);
    std::optional<Vec3f> yOrtho = unit(y - *z * dot(y, *z));
    if (!yOrtho) return std::nullopt;
    Mat4 r = m;
    setColumn(r, 0, cross(*yOrtho, *z));
    setColumn(r, 1, *yOrtho);
    setColumn(r, 2, *z);
    if (!isFinite(column(r, 3))) return std::nullopt;
    return r;
}

std::optional<CameraDesc> convertCamera(LoadContext& ctx, const tinygltf::Node& node, int nodeIndex,
                                        const Mat4& toWorld) {
    int index = node.camera;
    const tinygltf::Camera& src = checkedAt(ctx.model.cameras, index, "camera");
    CameraDesc cam;
    cam.name = !src.name.empty()    ? src.name
               : !node.name.empty() ? node.name
                                    : "camera" + std::to_string(index);
    if (src.type == "perspective")
        fillPerspective(ctx, src.perspective, index, cam);
    else if (src.type == "orthographic")
        fillOrthographic(src.orthographic, index, cam);
    else
        failf("camera {}: unknown type '{}'", index, printableUri(src.type));

    std::optional<Mat4> rigid = orthonormalized(toWorld);
    if (!rigid) {
        ctx.warn(fmt::format("node {}: camera '{}' has a degenerate transform; skipping it",
                             nodeIndex, cam.name));
        return std::nullopt;
    }
    if (hasScale(toWorld))
        ctx.warn(fmt::format("node {}: camera '{}' transform has scale; removing it", nodeIndex,
                             cam.name));
    cam.cameraToWorld = *rigid;
    return cam;
}

}  // namespace partita::gltf
