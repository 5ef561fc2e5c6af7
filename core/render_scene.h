// The scene as integrators see it: SceneData plus an Embree BVH, BSDF construction at hit
// points, and the light list with its power-proportional selection distribution.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "bsdf.h"
#include "light.h"
#include "ray.h"
#include "sampling.h"
#include "scene_data.h"
#include "surface_hit.h"

namespace partita {

class RenderScene {
public:
    /// Builds the BVH and the lights. Throws std::runtime_error if Embree fails.
    explicit RenderScene(SceneData data);
    ~RenderScene();
    RenderScene(const RenderScene&) = delete;
    RenderScene& operator=(const RenderScene&) = delete;

    const SceneData& data() const { return data_; }
    const Bounds3f& bounds() const { return bounds_; }

    /// Closest hit along the ray, within (0, ray.tMax).
    std::optional<SurfaceHit> intersect(const Ray& ray) const;
    /// Whether anything blocks the ray within (0, ray.tMax).
    bool occluded(const Ray& ray) const;
    /// Bare Embree closest-hit queries (rtcIntersect1, no hit shading), writing the hit distance
    /// or infinity. Only for measuring the ray-tracing kernel against the integrators.
    void intersectRaw(const Ray* rays, size_t count, float* tHit) const;

    const Material& materialOf(const SurfaceHit& hit) const;
    Bsdf bsdfAt(const SurfaceHit& hit) const;
    /// Radiance emitted from the hit point towards direction w (zero unless it is an area light).
    Rgb emittedRadiance(const SurfaceHit& hit, Vec3f w) const;

    const std::vector<Light>& lights() const { return lights_; }
    /// Index of the area light of the hit triangle, or -1.
    int areaLightIndex(const SurfaceHit& hit) const;
    /// Probability of choosing light i in lightSelection().
    float lightSelectionPmf(int i) const { return lightSelection_.pmf(uint32_t(i)); }
    const Distribution1D& lightSelection() const { return lightSelection_; }
    bool hasLights() const { return !lightSelection_.empty(); }

    /// Sample the light `lightIndex` as seen from ref; radiance includes textured emission.
    std::optional<LightSample> sampleLight(int lightIndex, Vec3f ref, Vec2f u) const;
    /// Solid-angle density at ref of sampleLight producing the area light point `hit`
    /// (light selection not included).
    float areaLightPdf(int lightIndex, Vec3f ref, const SurfaceHit& hit) const;

private:
    void buildAccel();
    void buildLights();
    SurfaceHit makeHit(uint32_t mesh, uint32_t tri, float u, float v, float t, const Ray& ray) const;

    SceneData data_;
    Material defaultMaterial_;
    Bounds3f bounds_;
    std::vector<Light> lights_;
    std::vector<std::vector<int>> triangleLight_;  // per mesh, per triangle: light index or -1
    Distribution1D lightSelection_;
    struct Embree;
    std::unique_ptr<Embree> embree_;
};

}  // namespace partita
