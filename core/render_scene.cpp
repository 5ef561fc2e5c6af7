#include "render_scene.h"

#include <embree3/rtcore.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "material_mapping.h"
#include "medium.h"
#include "path/short_edge_damping.h"

namespace partita {

struct RenderScene::Embree {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    ~Embree() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

namespace {
/// `ray` as Embree's single ray, searched over (0, ray.tMax).
RTCRay embreeRay(const Ray& ray) {
    RTCRay r;
    r.org_x = ray.o.x;
    r.org_y = ray.o.y;
    r.org_z = ray.o.z;
    r.dir_x = ray.d.x;
    r.dir_y = ray.d.y;
    r.dir_z = ray.d.z;
    r.tnear = 0;
    r.tfar = ray.tMax;
    r.mask = 0xFFFFFFFFu;
    r.flags = 0;
    r.time = 0;
    return r;
}

void embreeError(void*, RTCError code, const char* message) {
    spdlog::error("embree error {}: {}", int(code), message ? message : "");
}
}  // namespace

RenderScene::RenderScene(SceneData data)
    : data_(std::move(data)), embree_(std::make_unique<Embree>()) {
    bounds_ = data_.bounds();
    if (!bounds_.empty()) shortEdge_ = kShortEdgeShare * length(bounds_.diagonal());
    prepareMeshes();
    buildAccel();
    buildLights();
    for (const Material& m : data_.materials) hasAbsorption_ |= !isBlack(absorptionOf(m));
}

RenderScene::~RenderScene() = default;

namespace {
/// The unit shading normal from an interpolated vertex normal, flipped to ng's side; ng where
/// the interpolated normal has no direction.
Vec3f shadingNormal(Vec3f n, Vec3f ng) {
    float len = length(n);
    return (len > 0 && std::isfinite(len)) ? faceForward(n / len, ng) : ng;
}

/// Whether makeBsdf reads a texture for this material (then the BSDF varies over the surface).
bool bsdfUsesTextures(const Material& m) {
    return m.baseColorTexture.valid() || m.metallicRoughnessTexture.valid() ||
           m.transmissionTexture.valid();
}
}  // namespace

void RenderScene::prepareMeshes() {
    meshes_.resize(data_.meshes.size());
    size_t triangleCount = 0;
    for (const TriangleMesh& mesh : data_.meshes) triangleCount += mesh.triangleCount();
    triangles_.resize(triangleCount);
    uint32_t first = 0;
    for (size_t m = 0; m < data_.meshes.size(); ++m) {
        const TriangleMesh& mesh = data_.meshes[m];
        MeshInfo& info = meshes_[m];
        info.material =
            mesh.material >= 0 ? &data_.materials[size_t(mesh.material)] : &defaultMaterial_;
        info.firstTriangle = first;
        info.constantBsdf = !bsdfUsesTextures(*info.material);
        // Without textures makeBsdf's lobe does not depend on the point, only its frame does.
        if (info.constantBsdf)
            info.lobe = makeBsdf(*info.material, data_.textures, SurfacePoint{}).lobe();
        for (size_t t = 0; t < mesh.triangleCount(); ++t) {
            const uint32_t* idx = &mesh.indices[3 * t];
            const Vec3f &p0 = mesh.positions[idx[0]], &p1 = mesh.positions[idx[1]],
                        &p2 = mesh.positions[idx[2]];
            TriangleInfo& info = triangles_[first + t];
            info.ng = normalize(cross(p1 - p0, p2 - p0));
            const Vec3f &n0 = mesh.normals[idx[0]], &n1 = mesh.normals[idx[1]],
                        &n2 = mesh.normals[idx[2]];
            info.flat = n0 == n1 && n1 == n2;
            if (info.flat) info.shading = Frame::fromNormal(shadingNormal(n0, info.ng));
        }
        first += uint32_t(mesh.triangleCount());
    }
}

void RenderScene::buildAccel() {
    embree_->device = rtcNewDevice(nullptr);
    if (!embree_->device) throw std::runtime_error("cannot create the Embree device");
    rtcSetDeviceErrorFunction(embree_->device, embreeError, nullptr);
    embree_->scene = rtcNewScene(embree_->device);
    rtcSetSceneBuildQuality(embree_->scene, RTC_BUILD_QUALITY_HIGH);
    for (size_t m = 0; m < data_.meshes.size(); ++m) {
        const TriangleMesh& mesh = data_.meshes[m];
        RTCGeometry geom = rtcNewGeometry(embree_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        // Embree-owned buffers: Embree pads them for its vector loads.
        auto* vertices = static_cast<float*>(
            rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                    3 * sizeof(float), mesh.positions.size()));
        auto* indices = static_cast<uint32_t*>(
            rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(uint32_t), mesh.triangleCount()));
        if (!vertices || !indices)
            throw std::runtime_error("Embree could not allocate geometry buffers");
        for (size_t i = 0; i < mesh.positions.size(); ++i) {
            vertices[3 * i] = mesh.positions[i].x;
            vertices[3 * i + 1] = mesh.positions[i].y;
            vertices[3 * i + 2] = mesh.positions[i].z;
        }
        std::copy(mesh.indices.begin(), mesh.indices.end(), indices);
        rtcCommitGeometry(geom);
        rtcAttachGeometryByID(embree_->scene, geom, unsigned(m));
        rtcReleaseGeometry(geom);
    }
    rtcCommitScene(embree_->scene);
    if (rtcGetDeviceError(embree_->device) != RTC_ERROR_NONE)
        throw std::runtime_error("Embree failed to build the scene");
}

void RenderScene::buildLights() {
    for (size_t m = 0; m < data_.meshes.size(); ++m) {
        const TriangleMesh& mesh = data_.meshes[m];
        const Material& mat = *meshes_[m].material;
        if (!mat.isEmissive()) continue;
        for (size_t t = 0; t < mesh.triangleCount(); ++t) {
            AreaLight light;
            light.p0 = mesh.positions[mesh.indices[3 * t]];
            light.p1 = mesh.positions[mesh.indices[3 * t + 1]];
            light.p2 = mesh.positions[mesh.indices[3 * t + 2]];
            Vec3f n = cross(light.p1 - light.p0, light.p2 - light.p0);
            float len = length(n);
            if (!(len > 0) || !std::isfinite(len))
                continue;  // degenerate: never hit, never sampled
            light.normal = n / len;
            light.area = 0.5f * len;
            light.twoSided = mat.doubleSided;
            light.mesh = uint32_t(m);
            light.triangle = uint32_t(t);
            light.emission = mat.emissionScale();
            light.texturedEmission = mat.emissiveTexture.valid();
            triangles_[meshes_[m].firstTriangle + t].areaLight = int32_t(lights_.size());
            lights_.push_back(light);
        }
    }
    float radius = 0.5f * length(bounds_.diagonal());
    if (!std::isfinite(radius) || radius <= 0) radius = 1;
    for (const PunctualLightDesc& desc : data_.lights) {
        Rgb intensity = desc.color * desc.intensity;
        switch (desc.type) {
            case PunctualLightDesc::Type::Point:
                lights_.push_back(PointLight{desc.position, intensity});
                break;
            case PunctualLightDesc::Type::Spot: {
                SpotLight s;
                s.position = desc.position;
                s.direction = normalize(desc.direction);
                s.intensity = intensity;
                s.cosOuter = std::cos(desc.outerConeAngle);
                s.cosInner = std::max(std::cos(desc.innerConeAngle), s.cosOuter + 1e-6f);
                lights_.push_back(s);
                break;
            }
            case PunctualLightDesc::Type::Directional:
                lights_.push_back(DirectionalLight{normalize(desc.direction), intensity,
                                                   bounds_.center(), radius});
                break;
        }
    }
    if (data_.environment && !data_.environment->isBlack()) {
        environmentLight_ = int(lights_.size());
        lights_.push_back(EnvironmentLight{data_.environment, bounds_.center(), radius});
    }
    std::vector<float> power;
    power.reserve(lights_.size());
    for (const Light& l : lights_) power.push_back(lightPower(l));
    lightSelection_ = AliasTable(power);
}

bool RenderScene::intersect(const Ray& ray, SurfaceHit& hit) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray = embreeRay(ray);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(embree_->scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    fillHit(rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v, rh.ray.tfar, hit);
    return true;
}

void RenderScene::fillHit(uint32_t meshIndex, uint32_t tri, float u, float v, float t,
                          SurfaceHit& hit) const {
    const float w = 1 - u - v;
    const TriangleMesh& mesh = data_.meshes[meshIndex];
    const uint32_t* idx = &mesh.indices[3 * size_t(tri)];
    hit.t = t;
    hit.mesh = meshIndex;
    hit.triangle = tri;
    hit.barycentric = {u, v};
    // The barycentric point is more accurate than o + t d, which matters for ray offsets.
    hit.p = mesh.positions[idx[0]] * w + mesh.positions[idx[1]] * u + mesh.positions[idx[2]] * v;
    const TriangleInfo& info = triangles_[meshes_[meshIndex].firstTriangle + tri];
    hit.ng = info.ng;
    hit.ns = info.flat ? info.shading.n
                       : shadingNormal(mesh.normals[idx[0]] * w + mesh.normals[idx[1]] * u +
                                           mesh.normals[idx[2]] * v,
                                       info.ng);
}

void RenderScene::intersect8(const Ray* rays, int count, SurfaceHit* hits, bool* found) const {
    // Neighbouring camera rays share most of their traversal, so Embree's packet kernel visits
    // each BVH node once for all lanes that reach it.
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(32) int valid[8];
    alignas(32) RTCRayHit8 rh;
    for (int i = 0; i < 8; ++i) {
        const Ray& r = rays[std::min(i, count - 1)];
        valid[i] = i < count ? -1 : 0;
        rh.ray.org_x[i] = r.o.x;
        rh.ray.org_y[i] = r.o.y;
        rh.ray.org_z[i] = r.o.z;
        rh.ray.dir_x[i] = r.d.x;
        rh.ray.dir_y[i] = r.d.y;
        rh.ray.dir_z[i] = r.d.z;
        rh.ray.tnear[i] = 0;
        rh.ray.tfar[i] = r.tMax;
        rh.ray.mask[i] = 0xFFFFFFFFu;
        rh.ray.flags[i] = 0;
        rh.ray.time[i] = 0;
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect8(valid, embree_->scene, &context, &rh);
    for (int i = 0; i < count; ++i) {
        found[i] = rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
        if (found[i])
            fillHit(rh.hit.geomID[i], rh.hit.primID[i], rh.hit.u[i], rh.hit.v[i], rh.ray.tfar[i],
                    hits[i]);
    }
}

SurfaceHit RenderScene::hitAt(uint32_t mesh, uint32_t triangle, Vec2f barycentric) const {
    if (mesh >= data_.meshes.size() || size_t(triangle) * 3 >= data_.meshes[mesh].indices.size())
        throw std::out_of_range("no such mesh triangle");
    SurfaceHit hit;
    fillHit(mesh, triangle, barycentric.x, barycentric.y, 0, hit);
    return hit;
}

std::optional<SurfaceHit> RenderScene::intersect(const Ray& ray) const {
    SurfaceHit hit;
    if (!intersect(ray, hit)) return std::nullopt;
    return hit;
}

void RenderScene::intersectRaw(const Ray* rays, size_t count, float* tHit) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (size_t i = 0; i < count; ++i) {
        RTCRayHit rh;
        rh.ray = embreeRay(rays[i]);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(embree_->scene, &context, &rh);
        tHit[i] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? kInf : rh.ray.tfar;
    }
}

bool RenderScene::occluded(const Ray& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r = embreeRay(ray);
    rtcOccluded1(embree_->scene, &context, &r);
    return r.tfar < 0;  // Embree sets tfar to -inf on a hit
}

RenderScene::TextureCoordinates RenderScene::interpolateUv(uint32_t m, uint32_t tri,
                                                           Vec3f w) const {
    const TriangleMesh& mesh = data_.meshes[m];
    const uint32_t* idx = &mesh.indices[3 * size_t(tri)];
    TextureCoordinates tc;
    for (int set = 0; set < 2; ++set) {
        const auto& uvs = mesh.uvs[size_t(set)];
        if (uvs.empty()) continue;
        tc.uv[size_t(set)] = uvs[idx[0]] * w.x + uvs[idx[1]] * w.y + uvs[idx[2]] * w.z;
        tc.has[set] = true;
    }
    return tc;
}

RenderScene::TextureCoordinates RenderScene::textureCoordinates(const SurfaceHit& hit) const {
    float u = hit.barycentric.x, v = hit.barycentric.y;
    return interpolateUv(hit.mesh, hit.triangle, {1 - u - v, u, v});
}

Bsdf RenderScene::texturedBsdfAt(const SurfaceHit& hit) const {
    const MeshInfo& info = meshes_[hit.mesh];
    TextureCoordinates tc = textureCoordinates(hit);
    SurfacePoint sp;
    sp.ng = hit.ng;
    sp.ns = hit.ns;
    sp.uv = tc.uv;
    sp.hasUv[0] = tc.has[0];
    sp.hasUv[1] = tc.has[1];
    return makeBsdf(*info.material, data_.textures, sp);
}

Rgb RenderScene::emittedRadiance(const SurfaceHit& hit, Vec3f w) const {
    int li = areaLightIndex(hit);
    if (li < 0) return Rgb(0.0f);
    const auto& light = std::get<AreaLight>(lights_[size_t(li)]);
    if (!areaLightEmitsTowards(light, w)) return Rgb(0.0f);
    if (!light.texturedEmission) return light.emission;
    return evalEmission(materialOf(hit), data_.textures, textureCoordinates(hit).uv);
}

bool RenderScene::sampleAnyLight(int lightIndex, Vec3f ref, Vec2f u, LightSample& s) const {
    const Light& light = lights_[size_t(lightIndex)];
    if (const auto* env = std::get_if<EnvironmentLight>(&light))
        return sampleEnvironment(*env, ref, u, s);
    const auto* area = std::get_if<AreaLight>(&light);
    if (!area) {
        auto punctual = samplePunctualLight(light, ref);
        if (punctual) s = *punctual;
        return punctual.has_value();
    }
    Vec3f bary;
    if (!sampleAreaLight(*area, ref, u, s, bary)) return false;
    if (area->texturedEmission) {
        const Material& m = *meshes_[area->mesh].material;
        s.radiance =
            evalEmission(m, data_.textures, interpolateUv(area->mesh, area->triangle, bary).uv);
    } else {
        s.radiance = area->emission;
    }
    return !isBlack(s.radiance);
}

bool RenderScene::sampleEnvironment(const EnvironmentLight& env, Vec3f ref, Vec2f u,
                                    LightSample& s) const {
    if (!env.map->sample(u, s.wi, s.pdf)) return false;
    s.radiance = env.map->radiance(s.wi);
    // A point beyond the scene's bounding sphere, as for a directional light.
    s.distance = kInf;
    s.point = ref + s.wi * (2 * env.sceneRadius + length(ref - env.sceneCenter));
    s.normal = -s.wi;
    s.isDelta = false;
    return !isBlack(s.radiance);
}

Rgb RenderScene::environmentRadiance(Vec3f d) const {
    if (environmentLight_ < 0) return Rgb(0.0f);
    return std::get<EnvironmentLight>(lights_[size_t(environmentLight_)]).map->radiance(d);
}

float RenderScene::environmentPdf(Vec3f d) const {
    if (environmentLight_ < 0) return 0;
    return lightSelectionPmf(environmentLight_) *
           std::get<EnvironmentLight>(lights_[size_t(environmentLight_)]).map->pdf(d);
}

std::optional<LightSample> RenderScene::sampleLight(int lightIndex, Vec3f ref, Vec2f u) const {
    LightSample s;
    if (!sampleLight(lightIndex, ref, u, s)) return std::nullopt;
    return s;
}

float RenderScene::areaLightPdf(int lightIndex, Vec3f ref, const SurfaceHit& hit) const {
    return partita::areaLightPdf(std::get<AreaLight>(lights_[size_t(lightIndex)]), ref, hit.p);
}

}  // namespace partita
