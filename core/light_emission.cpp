#include "light_emission.h"

#include <cmath>

#include "math/frame.h"
#include "render_scene.h"
#include "sampling.h"

namespace partita {

namespace {

bool sampleAreaLe(const RenderScene& scene, const AreaLight& l, Vec2f uPos, Vec2f uDir,
                  EmittedRay& out) {
    Vec2f b = sampleUniformTriangle(uPos);
    // The point as a hit on its triangle, computed as a ray's hit is.
    out.hit = scene.hitAt(l.mesh, l.triangle, {b.y, 1 - b.x - b.y});
    out.origin = out.hit.p;
    out.normal = l.normal;
    // One side, or either side of a two-sided emitter with probability 1/2 (uDir.x reused).
    Vec3f n = l.normal;
    float sidePdf = 1;
    if (l.twoSided) {
        sidePdf = 0.5f;
        if (uDir.x < 0.5f) {
            uDir.x *= 2;
        } else {
            uDir.x = std::min(2 * uDir.x - 1, 0x1.fffffep-1f);
            n = -n;
        }
    }
    Vec3f local = sampleCosineHemisphere(uDir);
    if (local.z <= 0) return false;
    out.direction = Frame::fromNormal(n).toWorld(local);
    out.pdfPos = 1 / l.area;
    out.pdfDir = cosineHemispherePdf(local.z) * sidePdf;
    out.le = scene.emittedRadiance(out.hit, out.direction);
    return out.pdfDir > 0 && !isBlack(out.le);
}

}  // namespace

bool sampleLe(const RenderScene& scene, int light, Vec2f uPos, Vec2f uDir, EmittedRay& out) {
    const Light& l = scene.lights()[size_t(light)];
    out = {};
    if (const auto* area = std::get_if<AreaLight>(&l))
        return sampleAreaLe(scene, *area, uPos, uDir, out);
    if (const auto* point = std::get_if<PointLight>(&l)) {
        out.origin = point->position;
        out.direction = sampleUniformSphere(uDir);
        out.le = point->intensity;
        out.pdfPos = 1;
        out.pdfDir = uniformSpherePdf();
        return !isBlack(out.le);
    }
    if (const auto* spot = std::get_if<SpotLight>(&l)) {
        out.origin = spot->position;
        out.direction =
            Frame::fromNormal(spot->direction).toWorld(sampleUniformCone(uDir, spot->cosOuter));
        out.le = spot->intensity * spot->falloff(out.direction);
        out.pdfPos = 1;
        out.pdfDir = uniformConePdf(spot->cosOuter);
        return !isBlack(out.le);
    }
    if (const auto* env = std::get_if<EnvironmentLight>(&l)) {
        // A direction from the map; the ray comes from a disk perpendicular to it, beyond the
        // scene's bounding sphere, towards the scene.
        Vec3f towardsSky;
        if (!env->map->sample(uDir, towardsSky, out.pdfDir)) return false;
        Frame frame = Frame::fromNormal(towardsSky);
        Vec2f d = sampleConcentricDisk(uPos) * env->sceneRadius;
        out.origin =
            env->sceneCenter + towardsSky * (2 * env->sceneRadius) + frame.s * d.x + frame.t * d.y;
        out.direction = -towardsSky;
        out.le = env->map->radiance(towardsSky);
        out.pdfPos = 1 / (kPi * env->sceneRadius * env->sceneRadius);
        return !isBlack(out.le);
    }
    const auto& dir = std::get<DirectionalLight>(l);
    // A disk of the scene's radius, perpendicular to the light, outside the bounding sphere.
    Frame frame = Frame::fromNormal(dir.direction);
    Vec2f d = sampleConcentricDisk(uPos) * dir.sceneRadius;
    out.origin =
        dir.sceneCenter - dir.direction * (2 * dir.sceneRadius) + frame.s * d.x + frame.t * d.y;
    out.direction = dir.direction;
    out.le = dir.irradiance;
    out.pdfPos = 1 / directionalDiskArea(dir);
    out.pdfDir = 1;
    return !isBlack(out.le);
}

float emittedDirectionPdf(const Light& light, Vec3f n, Vec3f w) {
    if (const auto* area = std::get_if<AreaLight>(&light)) {
        float c = dot(n, w);
        if (!areaLightEmitsTowards(*area, w)) return 0;
        return std::abs(c) * kInvPi * (area->twoSided ? 0.5f : 1.0f);
    }
    if (std::holds_alternative<PointLight>(light)) return uniformSpherePdf();
    if (const auto* spot = std::get_if<SpotLight>(&light))
        return dot(spot->direction, w) >= spot->cosOuter ? uniformConePdf(spot->cosOuter) : 0;
    return 0;  // directional: a delta direction
}

float lightVertexDensity(const RenderScene& scene, int light, Vec3f towardsLight) {
    float pmf = scene.lightSelectionPmf(light);
    const Light& l = scene.lights()[size_t(light)];
    if (const auto* area = std::get_if<AreaLight>(&l)) return pmf / area->area;
    if (const auto* env = std::get_if<EnvironmentLight>(&l))
        return pmf * env->map->pdf(towardsLight);
    return pmf;
}

bool isInfiniteLight(const Light& light) {
    return std::holds_alternative<DirectionalLight>(light) ||
           std::holds_alternative<EnvironmentLight>(light);
}

bool cameraCanConnectTo(const Light& light) { return !isInfiniteLight(light); }

bool isHittableLight(const Light& light) {
    return std::holds_alternative<AreaLight>(light) ||
           std::holds_alternative<EnvironmentLight>(light);
}

float densityTowards(const Light& light, Vec3f from, Vec3f n, Vec3f to, Vec3f ngTo) {
    if (const auto* dir = std::get_if<DirectionalLight>(&light)) {
        // The ray's origin is uniform on the disk; projected along the light onto the vertex.
        // (`from` lies on the line through `to` along the light by construction.)
        float cosTo = isBlack(ngTo) ? 1.0f : absDot(ngTo, dir->direction);
        return cosTo / directionalDiskArea(*dir);
    }
    if (const auto* env = std::get_if<EnvironmentLight>(&light)) {
        // Likewise for the environment, along the direction from its far point.
        float cosTo = isBlack(ngTo) ? 1.0f : absDot(ngTo, normalize(to - from));
        return cosTo / (kPi * env->sceneRadius * env->sceneRadius);
    }
    Vec3f d = to - from;
    float dist2 = lengthSquared(d);
    if (!(dist2 > 0)) return 0;
    Vec3f w = d / std::sqrt(dist2);
    float cosTo = isBlack(ngTo) ? 1.0f : absDot(ngTo, w);
    return emittedDirectionPdf(light, n, w) * cosTo / dist2;
}

}  // namespace partita
