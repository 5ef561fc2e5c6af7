// The scene as integrators see it: SceneData plus an Embree BVH, BSDF construction at hit
// points, and the light list with its power-proportional selection distribution.
//
// Hit shading is on the path tracer's hot path, so what does not change per hit is prepared
// once here: each triangle's unit geometric normal and area-light index (and its shading frame
// when the three vertex normals agree, as on flat-shaded meshes), and each mesh's BSDF
// lobe when its material has no texture that the BSDF reads (then a hit only builds the shading
// frame). Texture coordinates are interpolated only for textured materials.
#pragma once

#include <algorithm>
#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "alias_table.h"
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
    /// The length below which the chains' target damps a path's edge
    /// (path/short_edge_damping.h): kShortEdgeShare of the bounding-box diagonal, or what
    /// setShortEdge gave (tests, to make the damping act everywhere; 0: none).
    float shortEdge() const { return shortEdge_; }
    void setShortEdge(float length) { shortEdge_ = std::max(0.0f, length); }

    /// Closest hit along the ray, within (0, ray.tMax).
    std::optional<SurfaceHit> intersect(const Ray& ray) const;
    /// The same query writing into `hit` (left unspecified on a miss, when it returns false).
    bool intersect(const Ray& ray, SurfaceHit& hit) const;
    /// Closest hits of `count` (1 to 8) rays traced together as one Embree packet: for coherent
    /// rays such as the camera rays of neighbouring pixels. hits[i] is set where found[i].
    void intersect8(const Ray* rays, int count, SurfaceHit* hits, bool* found) const;
    /// Whether anything blocks the ray within (0, ray.tMax).
    bool occluded(const Ray& ray) const;
    /// The hit record of the point with Embree barycentrics (u, v) on triangle `triangle` of mesh
    /// `mesh` (t = 0), as a ray would have found it: for rebuilding a stored path vertex.
    /// Throws std::out_of_range for a mesh or triangle that does not exist.
    SurfaceHit hitAt(uint32_t mesh, uint32_t triangle, Vec2f barycentric) const;
    /// Bare Embree closest-hit queries (rtcIntersect1, no hit shading), writing the hit distance
    /// or infinity. Only for measuring the ray-tracing kernel against the integrators.
    void intersectRaw(const Ray* rays, size_t count, float* tHit) const;

    const Material& materialOf(const SurfaceHit& hit) const { return *meshes_[hit.mesh].material; }
    Bsdf bsdfAt(const SurfaceHit& hit) const {
        const MeshInfo& info = meshes_[hit.mesh];
        // makeBsdf's frame and normals, with the lobe it would build (see prepareMeshes).
        if (info.constantBsdf) {
            const TriangleInfo& tri = triangleOf(hit);
            return Bsdf(tri.flat ? tri.shading : Frame::fromNormal(hit.ns), hit.ng, info.lobe);
        }
        return texturedBsdfAt(hit);
    }
    /// TEXCOORD_0 and TEXCOORD_1 at the hit; (0, 0) and `has` false for a set the mesh lacks.
    struct TextureCoordinates {
        std::array<Vec2f, 2> uv{};
        bool has[2] = {false, false};
    };
    TextureCoordinates textureCoordinates(const SurfaceHit& hit) const;
    /// Radiance emitted from the hit point towards direction w (zero unless it is an area light).
    Rgb emittedRadiance(const SurfaceHit& hit, Vec3f w) const;

    const std::vector<Light>& lights() const { return lights_; }
    /// Whether any material absorbs (KHR_materials_volume): path edges need transmittances.
    bool hasAbsorption() const { return hasAbsorption_; }
    /// Index of the area light of the hit triangle, or -1.
    int areaLightIndex(const SurfaceHit& hit) const { return triangleOf(hit).areaLight; }
    /// Probability of choosing light i in lightSelection().
    float lightSelectionPmf(int i) const { return lightSelection_.pmf(uint32_t(i)); }
    const AliasTable& lightSelection() const { return lightSelection_; }
    bool hasLights() const { return !lightSelection_.empty(); }

    /// Sample the light `lightIndex` as seen from ref; radiance includes textured emission.
    std::optional<LightSample> sampleLight(int lightIndex, Vec3f ref, Vec2f u) const;
    /// The same sample written into `out`; false (out unspecified) when there is none. Inline
    /// for the common case of next-event estimation, an area light of constant emission.
    bool sampleLight(int lightIndex, Vec3f ref, Vec2f u, LightSample& out) const {
        const auto* area = std::get_if<AreaLight>(&lights_[size_t(lightIndex)]);
        if (!area || area->texturedEmission) return sampleAnyLight(lightIndex, ref, u, out);
        Vec3f barycentric;
        if (!sampleAreaLight(*area, ref, u, out, barycentric)) return false;
        out.radiance = area->emission;  // not black: only emissive materials make area lights
        return true;
    }
    /// The environment light's index in lights(), or -1 when the scene has none.
    int environmentLightIndex() const { return environmentLight_; }
    bool hasEnvironment() const { return environmentLight_ >= 0; }
    /// Radiance arriving from direction d (towards the sky) from the environment; zero without.
    Rgb environmentRadiance(Vec3f d) const;
    /// Solid-angle density of next-event estimation choosing the environment and direction d
    /// (light selection included).
    float environmentPdf(Vec3f d) const;
    /// Solid-angle density at ref of sampleLight producing the area light point `hit`
    /// (light selection not included).
    float areaLightPdf(int lightIndex, Vec3f ref, const SurfaceHit& hit) const;

  private:
    /// Per mesh, prepared once.
    struct MeshInfo {
        const Material* material = nullptr;
        uint32_t firstTriangle = 0;  // of the mesh's triangles in triangles_
        bool constantBsdf = false;   // no texture feeds the BSDF: `lobe` holds on the whole mesh
        BsdfLobe lobe;
    };
    /// Per triangle, prepared once.
    struct TriangleInfo {
        Vec3f ng;                // unit normal from the winding
        int32_t areaLight = -1;  // index into lights_, or -1
        Frame shading;           // when `flat`: the shading frame, its normal the shading normal
        bool flat = false;       // the three vertex normals are equal: so is the frame everywhere
    };

    /// The hit record of Embree's hit (mesh, triangle, barycentrics u, v, distance t).
    void fillHit(uint32_t mesh, uint32_t tri, float u, float v, float t, SurfaceHit& hit) const;
    /// bsdfAt for a material with textures.
    Bsdf texturedBsdfAt(const SurfaceHit& hit) const;
    /// sampleLight for every kind of light (textured emission, punctual lights).
    bool sampleAnyLight(int lightIndex, Vec3f ref, Vec2f u, LightSample& out) const;
    bool sampleEnvironment(const EnvironmentLight& env, Vec3f ref, Vec2f u, LightSample& out) const;
    void prepareMeshes();
    void buildAccel();
    void buildLights();
    const TriangleInfo& triangleOf(const SurfaceHit& hit) const {
        return triangles_[meshes_[hit.mesh].firstTriangle + hit.triangle];
    }
    /// TEXCOORD_0/1 of mesh `m` at barycentric weights w (of the triangle's vertices 0, 1, 2).
    TextureCoordinates interpolateUv(uint32_t m, uint32_t tri, Vec3f w) const;

    SceneData data_;
    Material defaultMaterial_;
    Bounds3f bounds_;
    float shortEdge_ = 0;
    std::vector<MeshInfo> meshes_;
    std::vector<TriangleInfo> triangles_;  // all meshes' triangles, mesh by mesh
    std::vector<Light> lights_;
    AliasTable lightSelection_;
    int environmentLight_ = -1;
    bool hasAbsorption_ = false;
    struct Embree;
    std::unique_ptr<Embree> embree_;
};

}  // namespace partita
