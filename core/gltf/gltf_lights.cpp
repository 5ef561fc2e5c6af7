#include "gltf/gltf_lights.h"

#include <cfloat>
#include <cmath>

#include "gltf/gltf_common.h"

namespace partita::gltf {

namespace {

bool lightType(const std::string& type, PunctualLightDesc::Type& out) {
    if (type == "point")
        out = PunctualLightDesc::Type::Point;
    else if (type == "spot")
        out = PunctualLightDesc::Type::Spot;
    else if (type == "directional")
        out = PunctualLightDesc::Type::Directional;
    else
        return false;
    return true;
}

/// glTF requires 0 <= inner < outer <= pi/2; anything else is clamped into that range.
void fillSpotCone(LoadContext& ctx, const tinygltf::SpotLight& spot, int lightIndex,
                  PunctualLightDesc& light) {
    double o = spot.outerConeAngle, i = spot.innerConeAngle;
    bool valid = o > 0 && o <= kPi / 2 + 1e-6 && i >= 0 && i < o;
    float outer = clampedFloat(o, 1e-4f, kPi / 2, kPi / 4);
    float inner = clampedFloat(i, 0.f, outer, 0.f);
    if (inner >= outer) inner = 0.f;
    if (!valid)
        ctx.warn(
            fmt::format("light {}: spot cone angles (inner {}, outer {}) are invalid; using "
                        "({}, {})",
                        lightIndex, i, o, inner, outer));
    light.innerConeAngle = inner;
    light.outerConeAngle = outer;
}

void fillColorAndIntensity(LoadContext& ctx, const tinygltf::Light& src, int lightIndex,
                           PunctualLightDesc& light) {
    if (src.color.size() == 3)
        light.color = {clampedFloat(src.color[0], 0, FLT_MAX, 1),
                       clampedFloat(src.color[1], 0, FLT_MAX, 1),
                       clampedFloat(src.color[2], 0, FLT_MAX, 1)};
    else if (!src.color.empty())
        ctx.warn(fmt::format("light {}: color must have 3 numbers; using white", lightIndex));
    light.intensity = clampedFloat(src.intensity, 0, FLT_MAX, 1);
    if (!(src.intensity >= 0))
        ctx.warn(fmt::format("light {}: intensity {} is invalid; using {}", lightIndex,
                             src.intensity, light.intensity));
    light.range = clampedFloat(src.range, 0, FLT_MAX, 0);
}

}  // namespace

std::optional<PunctualLightDesc> convertNodeLight(LoadContext& ctx, const tinygltf::Node& node,
                                                  int nodeIndex, const Mat4& toWorld) {
    const tinygltf::Value* ext = findExtension(node.extensions, "KHR_lights_punctual");
    if (!ext) return std::nullopt;
    std::optional<int> lightIndex = intMember(*ext, "light");
    if (!lightIndex) failf("node {}: KHR_lights_punctual has no valid \"light\" index", nodeIndex);
    const tinygltf::Light& src = checkedAt(ctx.model.lights, *lightIndex, "light");

    PunctualLightDesc light;
    if (!lightType(src.type, light.type)) {
        ctx.warn(fmt::format("light {}: unknown type '{}'; skipping it", *lightIndex,
                             printableUri(src.type)));
        return std::nullopt;
    }
    light.name = !src.name.empty() ? src.name : "light" + std::to_string(*lightIndex);
    fillColorAndIntensity(ctx, src, *lightIndex, light);
    if (light.type == PunctualLightDesc::Type::Spot)
        fillSpotCone(ctx, src.spot, *lightIndex, light);

    light.position = toWorld.transformPoint(Vec3f(0, 0, 0));
    Vec3f direction = toWorld.transformVector(Vec3f(0, 0, -1));
    float len = length(direction);
    if (!isFinite(light.position) || !std::isfinite(len) || !(len > 0)) {
        ctx.warn(fmt::format("node {}: light '{}' has a degenerate transform; skipping it",
                             nodeIndex, light.name));
        return std::nullopt;
    }
    light.direction = direction / len;
    return light;
}

}  // namespace partita::gltf
