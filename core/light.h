// Light sources: emissive triangles (area lights, from emissive glTF materials) and
// KHR_lights_punctual point, spot and directional lights, and the environment.
//
// sampleLi() picks a point on the light as seen from a reference point and returns the
// incident radiance with its density in solid angle at the reference point; for delta lights
// (point, spot, directional) the density is 1 and `isDelta` is set, so MIS gives them full
// weight. pdfLi() is the solid-angle density an area light would have produced for a given
// point on it, for MIS when a BSDF-sampled ray hits it.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <variant>

#include "environment_map.h"
#include "math/vec.h"
#include "sampling.h"

namespace partita {

struct LightSample {
    Rgb radiance{0.0f};  // Li arriving at the reference point (before visibility)
    Vec3f wi;            // unit direction from the reference point to the light
    Vec3f point;         // point on the light (far away for directional lights)
    Vec3f normal;        // light surface normal (area lights), -wi otherwise
    float distance = 0;  // to `point` (kInf for directional lights)
    float pdf = 0;       // solid angle at the reference point; 1 for delta lights
    bool isDelta = false;
};

/// One emissive triangle. Emission is looked up through the material at the sampled point, so
/// textured emission works; `emission` is its untextured scale used for power estimates.
struct AreaLight {
    Vec3f p0, p1, p2;
    Vec3f normal;  // unit, from the winding (p1-p0) x (p2-p0)
    float area = 0;
    bool twoSided = false;
    uint32_t mesh = 0, triangle = 0;
    Rgb emission{0.0f};
    /// The material has an emissive texture: the radiance varies over the triangle and must be
    /// looked up; otherwise it is `emission` everywhere.
    bool texturedEmission = false;
};

struct PointLight {
    Vec3f position;
    Rgb intensity{0.0f};  // radiant intensity
};

struct SpotLight {
    Vec3f position, direction;  // direction: where the light points, unit
    Rgb intensity{0.0f};
    float cosInner = 1, cosOuter = 0;
    /// glTF's smooth falloff between the inner and outer cones.
    float falloff(Vec3f wLight) const;
};

struct DirectionalLight {
    Vec3f direction;       // where light travels, unit
    Rgb irradiance{0.0f};  // on a surface facing the light
    Vec3f sceneCenter;     // to place the virtual source outside the scene
    float sceneRadius = 1;
};

/// The environment (environment_map.h) as a light: directions come from the map; for light
/// subpaths its rays start on a disk of the scene's radius outside the bounding sphere.
struct EnvironmentLight {
    std::shared_ptr<const EnvironmentMap> map;
    Vec3f sceneCenter;
    float sceneRadius = 1;
};

using Light = std::variant<AreaLight, PointLight, SpotLight, DirectionalLight, EnvironmentLight>;

/// Power of a light (luminance-weighted), used to choose lights in proportion to their power.
float lightPower(const Light& light);
bool isDeltaLight(const Light& light);

/// Whether the area light emits along direction w leaving its surface.
inline bool areaLightEmitsTowards(const AreaLight& light, Vec3f w) {
    float c = dot(light.normal, w);
    return light.twoSided ? c != 0 : c > 0;
}

/// Sample a point on an area light uniformly by area, as seen from `ref`; false when it sends
/// nothing towards ref. Fills everything but `radiance` (the caller evaluates the material,
/// which may be textured: RenderScene::sampleLight). Inline: next-event estimation calls it
/// once per path vertex.
inline bool sampleAreaLight(const AreaLight& l, Vec3f ref, Vec2f u, LightSample& s,
                            Vec3f& barycentric) {
    Vec2f b = sampleUniformTriangle(u);
    barycentric = {b.x, b.y, 1 - b.x - b.y};
    Vec3f p = l.p0 * barycentric.x + l.p1 * barycentric.y + l.p2 * barycentric.z;
    Vec3f d = p - ref;
    float dist2 = lengthSquared(d);
    if (dist2 <= 0) return false;
    // Emits towards ref, along -d; this also rules out a zero cosine.
    float cosD = -dot(l.normal, d);  // |d| cos(theta) at the light, signed
    if (l.twoSided ? cosD == 0 : !(cosD > 0)) return false;
    float dist = std::sqrt(dist2);
    s.wi = d * (1 / dist);
    s.point = p;
    s.normal = l.normal;
    s.distance = dist;
    // Uniform area density 1/A converted to solid angle: d^2 / (|cos| A) with
    // |cos| = |cosD| / dist. Written without wi, so it does not wait for the division above.
    s.pdf = dist2 * dist / (std::abs(cosD) * l.area);
    s.isDelta = false;
    return true;
}

/// Solid-angle density at `ref` of sampling `pointOnLight` on `light` by sampleAreaLight.
float areaLightPdf(const AreaLight& light, Vec3f ref, Vec3f pointOnLight);

std::optional<LightSample> samplePunctualLight(const Light& light, Vec3f ref);

}  // namespace partita
