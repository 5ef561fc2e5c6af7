// Lights as the start of a light subpath (bidirectional methods): sampling an emitted ray
// (sampleLe) and the densities of doing so (pdfLe), per kind of light.
//
// Densities are split the way a path's vertices need them in area measure:
// - the light vertex x_M itself: lightVertexDensity() = P(light) * position density, where the
//   position density is 1 / area for an area light and 1 for point, spot and directional lights
//   (a Dirac delta, which cancels between every strategy that can sample such a path);
// - the next vertex x_{M-1}: densityTowards(), the direction density converted to area at that
//   vertex (pdfDir |cos| / d^2), or for a directional light the density of the emitted ray's
//   origin on its disk projected onto the vertex (|cos| / (pi r^2)), since its direction is the
//   delta and its position the sampled quantity.
#pragma once

#include "light.h"
#include "math/vec.h"
#include "surface_hit.h"

namespace partita {

class RenderScene;

/// A ray leaving a light.
struct EmittedRay {
    Vec3f origin;      // on the light (on a disk outside the scene for a directional light)
    Vec3f direction;   // unit
    Vec3f normal;      // area lights: the emitting triangle's normal; zero otherwise
    Rgb le{0.0f};      // radiance (area), intensity (point, spot), irradiance (directional)
    float pdfPos = 0;  // area density of the origin (1 for point and spot: a delta)
    float pdfDir = 0;  // solid-angle density of the direction (1 for directional: a delta)
    SurfaceHit hit;    // area lights: the point as a hit on its triangle (for textures)
};

/// Samples a ray from light `light` of the scene (uPos picks the point, uDir the direction;
/// a two-sided area light picks its side with uDir.x). False when the light sends nothing.
bool sampleLe(const RenderScene& scene, int light, Vec2f uPos, Vec2f uDir, EmittedRay& out);

/// Solid-angle density with which sampleLe emits direction w (unit, leaving the light) from a
/// point with normal n (area lights). Zero for directional lights (a delta direction) and for
/// directions the light does not emit into.
float emittedDirectionPdf(const Light& light, Vec3f n, Vec3f w);

/// Position density of the light vertex times the light's selection probability (see above).
/// For the environment, whose vertex is a direction, the solid-angle density of `towardsLight`
/// (the unit direction from the scene towards it) instead.
float lightVertexDensity(const RenderScene& scene, int light, Vec3f towardsLight = {});

/// Lights infinitely far away (directional, environment): rays from them start on a disk.
bool isInfiniteLight(const Light& light);
/// Whether a pinhole camera can connect to a vertex on the light (not for a delta direction nor
/// the environment, which the camera sees by its own rays).
bool cameraCanConnectTo(const Light& light);
/// Whether camera paths can hit the light (area lights and the environment).
bool isHittableLight(const Light& light);

/// Area density at point `to` (geometric normal ngTo, or zero for a point with no surface) of
/// the light subpath's first vertex, given the light vertex at `from` with normal `n`.
float densityTowards(const Light& light, Vec3f from, Vec3f n, Vec3f to, Vec3f ngTo);

/// Radius of the disk a directional light's rays start from (the scene's bounding sphere).
inline float directionalDiskArea(const DirectionalLight& l) {
    return kPi * l.sceneRadius * l.sceneRadius;
}

}  // namespace partita
