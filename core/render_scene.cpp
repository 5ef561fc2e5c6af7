#include "render_scene.h"

#include <embree3/rtcore.h>
#include <spdlog/spdlog.h>

#include <stdexcept>
#include <string>

#include "material_mapping.h"

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
void embreeError(void*, RTCError code, const char* message) {
    spdlog::error("embree error {}: {}", int(code), message ? message : "");
}
}  // namespace

RenderScene::RenderScene(SceneData data) : data_(std::move(data)), embree_(std::make_unique<Embree>()) {
    bounds_ = data_.bounds();
    buildAccel();
    buildLights();
}

RenderScene::~RenderScene() = default;

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
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size()));
        auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), mesh.triangleCount()));
        if (!vertices || !indices) throw std::runtime_error("Embree could not allocate geometry buffers");
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
    triangleLight_.resize(data_.meshes.size());
    for (size_t m = 0; m < data_.meshes.size(); ++m) {
        const TriangleMesh& mesh = data_.meshes[m];
        triangleLight_[m].assign(mesh.triangleCount(), -1);
        const Material& mat = mesh.material >= 0 ? data_.materials[mesh.material] : defaultMaterial_;
        if (!mat.isEmissive()) continue;
        for (size_t t = 0; t < mesh.triangleCount(); ++t) {
            AreaLight light;
            light.p0 = mesh.positions[mesh.indices[3 * t]];
            light.p1 = mesh.positions[mesh.indices[3 * t + 1]];
            light.p2 = mesh.positions[mesh.indices[3 * t + 2]];
            Vec3f n = cross(light.p1 - light.p0, light.p2 - light.p0);
            float len = length(n);
            if (!(len > 0) || !std::isfinite(len)) continue;  // degenerate: never hit, never sampled
            light.normal = n / len;
            light.area = 0.5f * len;
            light.twoSided = mat.doubleSided;
            light.mesh = uint32_t(m);
            light.triangle = uint32_t(t);
            light.emission = mat.emissionScale();
            triangleLight_[m][t] = int(lights_.size());
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
                lights_.push_back(DirectionalLight{normalize(desc.direction), intensity, bounds_.center(), radius});
                break;
        }
    }
    std::vector<float> power;
    power.reserve(lights_.size());
    for (const Light& l : lights_) power.push_back(lightPower(l));
    lightSelection_ = Distribution1D(power);
}

std::optional<SurfaceHit> RenderScene::intersect(const Ray& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray.org_x = ray.o.x;
    rh.ray.org_y = ray.o.y;
    rh.ray.org_z = ray.o.z;
    rh.ray.dir_x = ray.d.x;
    rh.ray.dir_y = ray.d.y;
    rh.ray.dir_z = ray.d.z;
    rh.ray.tnear = 0;
    rh.ray.tfar = ray.tMax;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.flags = 0;
    rh.ray.time = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(embree_->scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    return makeHit(rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v, rh.ray.tfar, ray);
}

void RenderScene::intersectRaw(const Ray* rays, size_t count, float* tHit) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (size_t i = 0; i < count; ++i) {
        RTCRayHit rh;
        rh.ray.org_x = rays[i].o.x;
        rh.ray.org_y = rays[i].o.y;
        rh.ray.org_z = rays[i].o.z;
        rh.ray.dir_x = rays[i].d.x;
        rh.ray.dir_y = rays[i].d.y;
        rh.ray.dir_z = rays[i].d.z;
        rh.ray.tnear = 0;
        rh.ray.tfar = rays[i].tMax;
        rh.ray.mask = 0xFFFFFFFFu;
        rh.ray.flags = 0;
        rh.ray.time = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(embree_->scene, &context, &rh);
        tHit[i] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? kInf : rh.ray.tfar;
    }
}

bool RenderScene::occluded(const Ray& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
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
    rtcOccluded1(embree_->scene, &context, &r);
    return r.tfar < 0;  // Embree sets tfar to -inf on a hit
}

SurfaceHit RenderScene::makeHit(uint32_t meshIndex, uint32_t tri, float u, float v, float t, const Ray&) const {
    const TriangleMesh& mesh = data_.meshes[meshIndex];
    uint32_t i0 = mesh.indices[3 * tri], i1 = mesh.indices[3 * tri + 1], i2 = mesh.indices[3 * tri + 2];
    float w = 1 - u - v;
    SurfaceHit hit;
    hit.t = t;
    hit.mesh = meshIndex;
    hit.triangle = tri;
    hit.barycentric = {u, v};
    const Vec3f &p0 = mesh.positions[i0], &p1 = mesh.positions[i1], &p2 = mesh.positions[i2];
    // The barycentric point is more accurate than o + t d, which matters for ray offsets.
    hit.p = p0 * w + p1 * u + p2 * v;
    hit.ng = normalize(cross(p1 - p0, p2 - p0));
    Vec3f ns = mesh.normals[i0] * w + mesh.normals[i1] * u + mesh.normals[i2] * v;
    float nsLen = length(ns);
    hit.ns = (nsLen > 0 && std::isfinite(nsLen)) ? faceForward(ns / nsLen, hit.ng) : hit.ng;
    for (int set = 0; set < 2; ++set) {
        const auto& uvs = mesh.uvs[set];
        if (uvs.empty()) continue;
        hit.uv[set] = uvs[i0] * w + uvs[i1] * u + uvs[i2] * v;
        hit.hasUv[set] = true;
    }
    return hit;
}

const Material& RenderScene::materialOf(const SurfaceHit& hit) const {
    int m = data_.meshes[hit.mesh].material;
    return m >= 0 ? data_.materials[m] : defaultMaterial_;
}

Bsdf RenderScene::bsdfAt(const SurfaceHit& hit) const {
    SurfacePoint sp;
    sp.ng = hit.ng;
    sp.ns = hit.ns;
    sp.uv = hit.uv;
    sp.hasUv[0] = hit.hasUv[0];
    sp.hasUv[1] = hit.hasUv[1];
    return makeBsdf(materialOf(hit), data_.textures, sp);
}

int RenderScene::areaLightIndex(const SurfaceHit& hit) const { return triangleLight_[hit.mesh][hit.triangle]; }

Rgb RenderScene::emittedRadiance(const SurfaceHit& hit, Vec3f w) const {
    int li = areaLightIndex(hit);
    if (li < 0) return Rgb(0.0f);
    const auto& light = std::get<AreaLight>(lights_[li]);
    if (!areaLightEmitsTowards(light, w)) return Rgb(0.0f);
    return evalEmission(materialOf(hit), data_.textures, hit.uv);
}

std::optional<LightSample> RenderScene::sampleLight(int lightIndex, Vec3f ref, Vec2f u) const {
    const Light& light = lights_[lightIndex];
    const auto* area = std::get_if<AreaLight>(&light);
    if (!area) return samplePunctualLight(light, ref);
    Vec3f bary;
    auto s = sampleAreaLight(*area, ref, u, bary);
    if (!s) return std::nullopt;
    const TriangleMesh& mesh = data_.meshes[area->mesh];
    std::array<Vec2f, 2> uv{};
    for (int set = 0; set < 2; ++set) {
        const auto& uvs = mesh.uvs[set];
        if (uvs.empty()) continue;
        const uint32_t* idx = &mesh.indices[3 * area->triangle];
        uv[set] = uvs[idx[0]] * bary.x + uvs[idx[1]] * bary.y + uvs[idx[2]] * bary.z;
    }
    int mat = mesh.material;
    s->radiance = evalEmission(mat >= 0 ? data_.materials[mat] : defaultMaterial_, data_.textures, uv);
    if (isBlack(s->radiance)) return std::nullopt;
    return s;
}

float RenderScene::areaLightPdf(int lightIndex, Vec3f ref, const SurfaceHit& hit) const {
    return partita::areaLightPdf(std::get<AreaLight>(lights_[lightIndex]), ref, hit.p);
}

}  // namespace partita
