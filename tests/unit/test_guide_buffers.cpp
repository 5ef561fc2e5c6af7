// The guide buffers of `guided` (paper Sec. 5.1.1): the G-buffer of the first non-specular vertex
// per pixel, checked against rays traced independently (the scene's single-ray query, and an
// ideal sphere for the glass and the mirror); the per-partition pre-pass images.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "camera.h"
#include "gltf/gltf_loader.h"
#include "guide/gbuffer.h"
#include "partition/partition.h"
#include "partition/partition_images.h"
#include "partition/prepass.h"
#include "render_helpers.h"
#include "renderer.h"
#include "scene_builders.h"
#include "thread_pool.h"

namespace partita {
namespace {

RenderScene loadScene(const std::string& name) {
    return RenderScene(
        loadGltfFile(std::string(PARTITA_SCENES_DIR) + "/" + name + "/" + name + ".gltf"));
}

/// What buildGBuffer needs, for a scene at width x height.
struct GuideRun {
    const RenderScene& scene;
    Camera camera;
    RenderSettings settings;
    ThreadPool pool;
    std::atomic<bool> cancel{false};
    RenderObserver observer;

    GuideRun(const RenderScene& s, int width, int height, int maxDepth = 16, int threads = 2)
        : scene(s), camera(resolveCamera(s.data(), ""), width, height), pool(threads) {
        settings.width = width;
        settings.height = height;
        settings.maxDepth = maxDepth;
        settings.previewIntervalSeconds = 0;
        settings.maxTypeLayers = 1024;
    }
    RenderContext context() { return {scene, camera, settings, pool, cancel, observer}; }
    GBuffer gbuffer() { return buildGBuffer(context()); }
};

int meshNamed(const RenderScene& scene, const std::string& name) {
    const auto& meshes = scene.data().meshes;
    for (size_t i = 0; i < meshes.size(); ++i)
        if (meshes[i].name == name) return int(i);
    ADD_FAILURE() << "no mesh " << name;
    return -1;
}

// cornell-glass as scenes/generate.py writes it: a box x in [-1, 1], y in [0, 1.9741],
// z in [-1.00576, 5.3223]; spheres of radius 0.33.
constexpr float kBoxX = 1, kFloor = 0, kCeiling = 1.9741007f, kBack = -1.0057554f,
                kFront = 5.3223023f;
const Vec3f kGlassCentre{0.42f, 0.331f, 0.28f}, kMirrorCentre{-0.42f, 0.331f, -0.38f};
constexpr float kSphereRadius = 0.33f;

/// Where a ray from inside the box meets its walls.
Vec3f boxExit(Vec3f o, Vec3f d) {
    float t = 1e30f;
    auto plane = [&](float oc, float dc, float at) {
        if (dc == 0) return;
        float s = (at - oc) / dc;
        if (s > 1e-5f) t = std::min(t, s);
    };
    plane(o.x, d.x, -kBoxX);
    plane(o.x, d.x, kBoxX);
    plane(o.y, d.y, kFloor);
    plane(o.y, d.y, kCeiling);
    plane(o.z, d.z, kBack);
    plane(o.z, d.z, kFront);
    return o + d * t;
}

/// The far hit of the ray (unit d) with the ideal sphere, or nullopt.
std::optional<float> sphereHit(Vec3f o, Vec3f d, Vec3f c, float r, bool far) {
    Vec3f oc = o - c;
    float b = dot(oc, d), cc = dot(oc, oc) - r * r, disc = b * b - cc;
    if (disc < 0) return std::nullopt;
    float t = far ? -b + std::sqrt(disc) : -b - std::sqrt(disc);
    if (t <= 1e-5f) return std::nullopt;
    return t;
}

/// Unpolarised Fresnel reflectance for cosine cosI on the side of index n1 into n2.
double fresnel(double cosI, double n1, double n2) {
    double sinT = n1 / n2 * std::sqrt(std::max(0.0, 1 - cosI * cosI));
    if (sinT >= 1) return 1;
    double cosT = std::sqrt(1 - sinT * sinT);
    double rs = (n1 * cosI - n2 * cosT) / (n1 * cosI + n2 * cosT);
    double rp = (n2 * cosI - n1 * cosT) / (n2 * cosI + n1 * cosT);
    return 0.5 * (rs * rs + rp * rp);
}

/// Snell's law for unit d arriving at unit normal n (facing d's origin), n1 -> n2.
Vec3f refracted(Vec3f d, Vec3f n, double n1, double n2) {
    double eta = n1 / n2, cosI = -dot(d, n);
    double k = 1 - eta * eta * (1 - cosI * cosI);
    return normalize(d * float(eta) + n * float(eta * cosI - std::sqrt(k)));
}

TEST(GBuffer, WallsHaveTheirNormalAndAlbedoOnCornellGlass) {
    RenderScene scene = loadScene("cornell-glass");
    GuideRun run(scene, 32, 24);
    GBuffer g = run.gbuffer();
    ASSERT_EQ(g.width(), 32);
    ASSERT_EQ(g.height(), 24);
    EXPECT_EQ(g.bytes(), size_t(32 * 24 * 40));
    // The walls' inward normals and base colours (scenes/generate.py), and the hit of the
    // scene's own single-ray query through the same pixel centre.
    float white = luminance({0.73f, 0.71f, 0.68f});
    std::map<int, std::pair<Vec3f, float>> walls = {
        {meshNamed(scene, "floor"), {{0, 1, 0}, white}},
        {meshNamed(scene, "ceiling"), {{0, -1, 0}, white}},
        {meshNamed(scene, "back_wall"), {{0, 0, 1}, white}},
        {meshNamed(scene, "left_wall"), {{1, 0, 0}, luminance({0.63f, 0.065f, 0.05f})}},
        {meshNamed(scene, "right_wall"), {{-1, 0, 0}, luminance({0.14f, 0.45f, 0.091f})}}};
    std::map<int, int> checked;
    for (int y = 0; y < g.height(); ++y)
        for (int x = 0; x < g.width(); ++x) {
            std::optional<SurfaceHit> hit =
                scene.intersect(run.camera.generateRay({float(x) + 0.5f, float(y) + 0.5f}));
            ASSERT_TRUE(hit) << "cornell-glass is closed";
            auto wall = walls.find(int(hit->mesh));
            if (wall == walls.end()) continue;
            const GBufferTexel& t = g.at(x, y);
            ASSERT_TRUE(t.valid) << x << " " << y;
            EXPECT_EQ(t.surface, hit->mesh);
            EXPECT_EQ(t.specularVertices, 0);
            EXPECT_FLOAT_EQ(t.cameraTerm, 1.0f);
            EXPECT_LT(length(t.position - hit->p), 1e-4f);
            EXPECT_LT(length(t.normal - wall->second.first), 1e-5f) << x << " " << y;
            EXPECT_NEAR(t.albedo, wall->second.second, 1e-5f);
            ++checked[wall->first];
        }
    EXPECT_EQ(checked.size(), walls.size()) << "every wall is seen";
}

TEST(GBuffer, PixelsThroughTheGlassSphereSeeBelowOrBehindItAsAnIdealSphereDoes) {
    RenderScene scene = loadScene("cornell-glass");
    GuideRun run(scene, 32, 24);
    GBuffer g = run.gbuffer();
    std::optional<Vec2f> centre = run.camera.rasterOf(kGlassCentre);
    ASSERT_TRUE(centre);
    int checked = 0;
    int cx = int(centre->x), cy = int(centre->y);
    for (int y = cy - 1; y <= cy + 1; ++y)
        for (int x = cx - 1; x <= cx + 1; ++x) {
            const GBufferTexel& t = g.at(x, y);
            ASSERT_TRUE(t.valid) << x << " " << y;
            EXPECT_GE(t.specularVertices, 2);
            EXPECT_GT(t.cameraTerm, 0.0f);
            EXPECT_LE(t.cameraTerm, 1.0f);
            EXPECT_NE(int(t.surface), meshNamed(scene, "glass_sphere"));
            EXPECT_TRUE(t.position.y < kGlassCentre.y || t.position.z < kGlassCentre.z)
                << "below or behind the sphere";
            // The same ray through an ideal sphere (the mesh is a 32 x 20 UV sphere with smooth
            // normals): refracted in and out, then to the walls.
            Ray r = run.camera.generateRay({float(x) + 0.5f, float(y) + 0.5f});
            std::optional<float> tIn = sphereHit(r.o, r.d, kGlassCentre, kSphereRadius, false);
            ASSERT_TRUE(tIn);
            Vec3f p1 = r.o + r.d * *tIn, n1 = normalize(p1 - kGlassCentre);
            double f1 = fresnel(-dot(r.d, n1), 1.0, 1.5);
            Vec3f d1 = refracted(r.d, n1, 1.0, 1.5);
            std::optional<float> tOut = sphereHit(p1, d1, kGlassCentre, kSphereRadius, true);
            ASSERT_TRUE(tOut);
            Vec3f p2 = p1 + d1 * *tOut, n2 = normalize(kGlassCentre - p2);
            double f2 = fresnel(-dot(d1, n2), 1.5, 1.0);
            ASSERT_LT(f2, 1) << "no total internal reflection near the centre";
            Vec3f d2 = refracted(d1, n2, 1.5, 1.0);
            EXPECT_EQ(t.specularVertices, 2);
            EXPECT_LT(length(t.position - boxExit(p2, d2)), 0.02f) << x << " " << y;
            EXPECT_NEAR(t.cameraTerm, (1 - f1) * (1 - f2), 0.01) << x << " " << y;
            ++checked;
        }
    EXPECT_EQ(checked, 9);
}

TEST(GBuffer, PixelsOnTheMirrorSphereSeeItsReflection) {
    RenderScene scene = loadScene("cornell-glass");
    GuideRun run(scene, 32, 24);
    GBuffer g = run.gbuffer();
    std::optional<Vec2f> centre = run.camera.rasterOf(kMirrorCentre);
    ASSERT_TRUE(centre);
    int x = int(centre->x), y = int(centre->y);
    const GBufferTexel& t = g.at(x, y);
    ASSERT_TRUE(t.valid);
    EXPECT_EQ(t.specularVertices, 1);
    Ray r = run.camera.generateRay({float(x) + 0.5f, float(y) + 0.5f});
    std::optional<float> tIn = sphereHit(r.o, r.d, kMirrorCentre, kSphereRadius, false);
    ASSERT_TRUE(tIn);
    Vec3f p = r.o + r.d * *tIn, n = normalize(p - kMirrorCentre);
    float cosI = -dot(r.d, n);
    Vec3f d = r.d + n * (2 * cosI);
    // The reflected ray travels ~6 m to the front wall, so the mesh's facets show: compare
    // directions (within 10 mrad) rather than points.
    Vec3f exit = boxExit(p, d);
    EXPECT_LT(length(normalize(t.position - p) - d), 0.01f)
        << "x_s " << t.position.x << " " << t.position.y << " " << t.position.z << ", ideal "
        << exit.x << " " << exit.y << " " << exit.z;
    // Schlick's Fresnel with F0 = 0.95 (the mirror's base colour).
    float schlick = 0.95f + 0.05f * std::pow(1 - cosI, 5.0f);
    EXPECT_NEAR(t.cameraTerm, schlick, 0.005f);
}

TEST(GBuffer, EmittersTheSkyAndDeepChainsAreInvalid) {
    {
        RenderScene scene = loadScene("cornell-glass");
        GuideRun run(scene, 32, 24);
        GBuffer g = run.gbuffer();
        int light = meshNamed(scene, "light"), lightPixels = 0;
        for (int y = 0; y < g.height(); ++y)
            for (int x = 0; x < g.width(); ++x) {
                std::optional<SurfaceHit> hit =
                    scene.intersect(run.camera.generateRay({float(x) + 0.5f, float(y) + 0.5f}));
                if (hit && int(hit->mesh) == light) {
                    EXPECT_FALSE(g.at(x, y).valid) << "the emitter is no x_s";
                    ++lightPixels;
                }
            }
        EXPECT_GT(lightPixels, 0);
        // The glass sphere's centre needs x_s as the third scattering vertex, the mirror's as
        // the second.
        std::optional<Vec2f> glass = run.camera.rasterOf(kGlassCentre),
                             mirror = run.camera.rasterOf(kMirrorCentre);
        for (int depth : {1, 2, 3}) {
            GuideRun shallow(scene, 32, 24, depth);
            GBuffer s = shallow.gbuffer();
            EXPECT_EQ(s.at(int(glass->x), int(glass->y)).valid, depth >= 3) << depth;
            EXPECT_EQ(s.at(int(mirror->x), int(mirror->y)).valid, depth >= 2) << depth;
        }
    }
    // A floor under an empty sky: the upper half of the image sees nothing.
    SceneData data;
    data.materials = {test::lambertMaterial(Rgb(0.5f))};
    data.meshes.push_back(test::quad({-50, 0, 50}, {100, 0, 0}, {0, 0, -100}, 0));
    data.cameras.push_back(test::lookAtCamera({0, 1, 0}, {0, 1, -1}, 0.8f));
    RenderScene open(std::move(data));
    GuideRun run(open, 16, 12);
    GBuffer g = run.gbuffer();
    for (int x = 0; x < 16; ++x) {
        EXPECT_FALSE(g.at(x, 0).valid);
        EXPECT_TRUE(g.at(x, 11).valid);
        EXPECT_EQ(g.at(x, 11).surface, 0u);
    }
}

TEST(GBuffer, IsTheSameForAnyThreadCountAndStopsOnCancel) {
    RenderScene scene = loadScene("cornell-glass");
    GuideRun one(scene, 40, 30, 16, 1), two(scene, 40, 30, 16, 2);
    GBuffer a = one.gbuffer(), b = two.gbuffer();
    ASSERT_EQ(a.texels().size(), b.texels().size());
    for (size_t i = 0; i < a.texels().size(); ++i) {
        const GBufferTexel &s = a.texels()[i], &t = b.texels()[i];
        EXPECT_TRUE(s.valid == t.valid && s.surface == t.surface &&
                    s.specularVertices == t.specularVertices && s.albedo == t.albedo &&
                    s.cameraTerm == t.cameraTerm && s.position == t.position &&
                    s.normal == t.normal)
            << i;
    }
    two.cancel = true;
    EXPECT_THROW(two.gbuffer(), RenderCancelled);
}

// ---- per-partition pre-pass images -------------------------------------------------------

struct PrepassRun {
    PrepassResult prepass;
    std::vector<Partition> partitions;
};

PrepassRun prepassOf(GuideRun& run, uint64_t samples, int k, uint64_t seed) {
    std::string why;
    BootstrapSampler sampler(run.scene, run.camera, run.settings.maxDepth, seed,
                             choosePrepassEstimator(run.scene, "auto", why));
    PrepassRun r;
    r.prepass = runPrepass(run.context(), sampler, samples);
    r.partitions = makePartitions(r.prepass, k);
    return r;
}

TEST(PrepassImages, EachMeanIsThePartitionsBAndPixelsWithoutACandidateAreZero) {
    RenderScene scene = loadScene("cornell-glass");
    GuideRun run(scene, 32, 24, 8);
    PrepassRun pre = prepassOf(run, 20000, 5, 7);
    ASSERT_GE(pre.partitions.size(), 4u);
    std::vector<std::vector<float>> images =
        partitionPrepassImages(pre.prepass, pre.partitions, 32, 24);
    ASSERT_EQ(images.size(), pre.partitions.size());
    for (size_t g = 0; g < pre.partitions.size(); ++g) {
        const Partition& p = pre.partitions[g];
        ASSERT_EQ(images[g].size(), size_t(32 * 24));
        double sum = 0;
        for (float v : images[g]) sum += v;
        EXPECT_NEAR(sum / double(images[g].size()), p.b, 1e-5 * p.b) << p.label;
        std::set<uint32_t> hit;
        for (const BootstrapCandidate& c : pre.prepass.candidatesB)
            if (p.holds(c.type)) hit.insert(c.pixel);
        for (uint32_t i = 0; i < images[g].size(); ++i) {
            if (hit.count(i))
                EXPECT_GT(images[g][i], 0.0f) << p.label << " " << i;
            else
                EXPECT_EQ(images[g][i], 0.0f) << p.label << " " << i;
        }
    }
}

TEST(PrepassImages, ARecordsPixelIsWhereItsRegeneratedPathLands) {
    RenderScene scene = loadScene("cornell-glass");
    GuideRun run(scene, 32, 24, 8);
    // bdpt: light tracing (t = 1) records too, with their splat's raster.
    BootstrapSampler sampler(scene, run.camera, 8, 3, StartupEstimator::Bidirectional);
    std::vector<BootstrapCandidate> candidates;
    uint64_t rays = 0;
    for (uint64_t i = 0; i < 300; ++i) sampler.sample(i, candidates, rays);
    int lightTraced = 0, cameraSide = 0;
    for (const BootstrapCandidate& c : candidates) {
        MarkovPath path;
        if (!sampler.regenerate(c, path, rays)) continue;
        int x = std::clamp(int(std::floor(path.raster.x)), 0, 31);
        int y = std::clamp(int(std::floor(path.raster.y)), 0, 23);
        EXPECT_EQ(c.pixel, uint32_t(y * 32 + x)) << c.sample << " s " << c.s << " t " << c.t;
        (c.t == 1 ? lightTraced : cameraSide)++;
    }
    EXPECT_GT(lightTraced, 10);
    EXPECT_GT(cameraSide, 100);
}

}  // namespace
}  // namespace partita
