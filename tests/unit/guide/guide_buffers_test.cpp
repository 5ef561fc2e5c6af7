// The guide buffers of `guided` (paper Sec. 5.1.1): the G-buffer of the first non-specular vertex
// per pixel, checked against rays traced independently (the scene's single-ray query, and an
// ideal sphere for the glass and the mirror); the per-partition pre-pass images; their
// edge-avoiding denoiser on exact cases (constants, supports), on noisy images with a known
// clean one, on thread counts, and its threshold against a BDPT reference's support.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>

#include "camera.h"
#include "gltf/gltf_loader.h"
#include "guide/denoise.h"
#include "guide/gbuffer.h"
#include "guide/support_mask.h"
#include "partition/partition.h"
#include "partition/partition_images.h"
#include "partition/prepass.h"
#include "render_helpers.h"
#include "renderer.h"
#include "rng.h"
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
        settings.everyTypeLayer = true;
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

// ---- the denoiser --------------------------------------------------------------------------

/// A key of the denoiser's regions: the surface and the specular chain's length.
uint32_t regionOf(const GBufferTexel& t) { return t.surface * 256u + t.specularVertices; }

TEST(Denoise, KeepsAConstantImageExactlyConstantOnEachSurface) {
    RenderScene scene = loadScene("cornell-glass");
    GuideRun run(scene, 48, 36);
    GBuffer g = run.gbuffer();
    std::vector<float> image(g.texels().size());
    for (size_t i = 0; i < image.size(); ++i) {
        const GBufferTexel& t = g.texels()[i];
        image[i] = t.valid ? 0.1f + 0.37f * float(regionOf(t) % 7) : 5.0f + float(i);
    }
    std::vector<std::vector<float>> out = denoisePartitions(g, {image, image}, {}, &run.pool);
    ASSERT_EQ(out.size(), 2u);
    for (const auto& o : out)
        for (size_t i = 0; i < image.size(); ++i) EXPECT_EQ(o[i], image[i]) << i;
}

TEST(Denoise, PreservesAPartitionsSupport) {
    RenderScene scene = loadScene("cornell-glass");
    GuideRun run(scene, 48, 36);
    GBuffer g = run.gbuffer();
    int floor = meshNamed(scene, "floor");
    // Noise on the floor seen directly, zero everywhere else (the floor seen through the
    // spheres included).
    Rng rng(5, 1);
    std::vector<float> image(g.texels().size(), 0.0f), sparse(image.size(), 0.0f);
    int support = 0;
    for (size_t i = 0; i < image.size(); ++i) {
        const GBufferTexel& t = g.texels()[i];
        if (!t.valid || int(t.surface) != floor || t.specularVertices != 0) continue;
        image[i] = rng.nextFloat();
        if (rng.nextFloat() < 0.1f) sparse[i] = 10 * rng.nextFloat();
        ++support;
    }
    ASSERT_GT(support, 100);
    std::vector<std::vector<float>> out = denoisePartitions(g, {image, sparse}, {}, &run.pool);
    for (size_t i = 0; i < image.size(); ++i) {
        const GBufferTexel& t = g.texels()[i];
        bool inside = t.valid && int(t.surface) == floor && t.specularVertices == 0;
        if (!inside) {
            EXPECT_EQ(out[0][i], 0.0f) << i;
            EXPECT_EQ(out[1][i], 0.0f) << i;
        } else {
            EXPECT_GT(out[0][i], 0.0f) << i;
        }
    }
}

/// A smooth image over the G-buffer: a slow function of the position, times the albedo.
float cleanValue(const GBufferTexel& t) {
    if (!t.valid) return 0;
    Vec3f p = t.position;
    return t.albedo * (0.6f + 0.3f * std::sin(2.1f * p.x + 0.7f) * std::cos(1.7f * p.y) +
                       0.1f * std::sin(1.3f * p.z));
}

double rmse(const std::vector<float>& a, const std::vector<float>& b, const GBuffer& g) {
    double sum = 0;
    int n = 0;
    for (size_t i = 0; i < a.size(); ++i)
        if (g.texels()[i].valid) {
            sum += double(a[i] - b[i]) * (a[i] - b[i]);
            ++n;
        }
    return std::sqrt(sum / std::max(1, n));
}

TEST(Denoise, ReducesTheErrorOfASparseNoisyImage) {
    RenderScene scene = loadScene("cornell-glass");
    GuideRun run(scene, 128, 96);
    GBuffer g = run.gbuffer();
    std::vector<float> clean(g.texels().size());
    for (size_t i = 0; i < clean.size(); ++i) clean[i] = cleanValue(g.texels()[i]);
    // Like a pre-pass image: a pixel holds a sample (the clean value / q, unbiased) with
    // probability q, else zero; and a dense Gaussian-noise case.
    std::vector<double> sparseFactors, denseFactors;
    for (uint64_t seed = 0; seed < 6; ++seed) {
        Rng rng(31, seed);
        const float q = 0.25f;
        std::vector<float> sparse(clean.size(), 0.0f), dense(clean.size(), 0.0f);
        for (size_t i = 0; i < clean.size(); ++i) {
            if (rng.nextFloat() < q) sparse[i] = clean[i] / q;
            float u1 = std::max(rng.nextFloat(), 1e-7f), u2 = rng.nextFloat();
            float gauss = std::sqrt(-2 * std::log(u1)) * std::cos(6.2831853f * u2);
            dense[i] = clean[i] * (1 + 0.5f * gauss);
        }
        std::vector<std::vector<float>> out = denoisePartitions(g, {sparse, dense}, {}, &run.pool);
        double sparseFactor = rmse(sparse, clean, g) / rmse(out[0], clean, g);
        double denseFactor = rmse(dense, clean, g) / rmse(out[1], clean, g);
        std::printf("seed %d: RMSE reduced %.2fx (sparse, q = %.2f), %.2fx (dense)\n", int(seed),
                    sparseFactor, q, denseFactor);
        sparseFactors.push_back(sparseFactor);
        denseFactors.push_back(denseFactor);
    }
    // The bar: averaging a pixel with its 8 neighbours divides independent noise's RMSE by
    // sqrt(9) = 3 (both images' noise is independent per pixel, of variance 3 clean^2 for the
    // sparse one); five edge-avoiding levels must beat that, by more than the spread of the
    // factor over the seeds allows to be luck (Student-t, two comparisons, family level 1e-3).
    // Measured: 8.7x to 10.7x (sparse) and 3.7x to 4.0x (dense).
    const double boxFactor = 3;
    test::MeanAndError sparse = test::meanAndError(sparseFactors);
    test::MeanAndError dense = test::meanAndError(denseFactors);
    EXPECT_GT(sparse.mean - test::statisticalTolerance(sparse, boxFactor, 2), boxFactor)
        << sparse.mean << " +- " << sparse.standardError;
    EXPECT_GT(dense.mean - test::statisticalTolerance(dense, boxFactor, 2), boxFactor)
        << dense.mean << " +- " << dense.standardError;
}

TEST(Denoise, IsTheSameForAnyThreadCount) {
    RenderScene scene = loadScene("cornell-glass");
    GuideRun run(scene, 64, 48);
    GBuffer g = run.gbuffer();
    Rng rng(9, 9);
    std::vector<std::vector<float>> images(3, std::vector<float>(g.texels().size()));
    for (auto& image : images)
        for (float& v : image) v = rng.nextFloat() < 0.2f ? rng.nextFloat() : 0.0f;
    ThreadPool one(1), two(2);
    auto a = denoisePartitions(g, images, {}, &one);
    auto b = denoisePartitions(g, images, {}, &two);
    auto c = denoisePartitions(g, images, {}, nullptr);
    for (size_t k = 0; k < images.size(); ++k) {
        EXPECT_EQ(a[k], b[k]);
        EXPECT_EQ(a[k], c[k]);
        EXPECT_NE(a[k], images[k]);
    }
    EXPECT_THROW(denoisePartitions(g, {std::vector<float>(5)}, {}, nullptr), std::invalid_argument);
}

TEST(Denoise, SupportMasksHoldTheThresholdInOneBitAPixel) {
    std::vector<std::vector<float>> d = {{0, 0.5f, 0.02f, 0.01f, 1, 0}, {1, 1, 1, 0, 0, 0}};
    SupportMasks m(d, 3, 2, 0.01f);
    EXPECT_EQ(m.partitions(), 2u);
    std::vector<bool> expect0 = {false, true, true, false, true, false};
    for (int i = 0; i < 6; ++i) {
        EXPECT_EQ(m.above(0, i % 3, i / 3), expect0[size_t(i)]) << i;
        EXPECT_EQ(m.above(1, i % 3, i / 3), i < 3) << i;
    }
    EXPECT_EQ(m.bytes(), 2 * sizeof(uint64_t));
    SupportAgreement a = supportAgreement(d[0], {0, 1, 1, 1, 0, 0}, 0.01f);
    EXPECT_EQ(a.referenceNonzero, 3u);
    EXPECT_EQ(a.referenceZero, 3u);
    EXPECT_DOUBLE_EQ(a.nonzeroAbove, 2.0 / 3);  // pixel 3 sits at epsilon
    EXPECT_DOUBLE_EQ(a.zeroBelow, 2.0 / 3);     // pixel 4 is above it
}

/// Per partition of a pre-pass, the luminance of a BDPT reference's layers of its types.
std::vector<std::vector<float>> partitionReferences(const LayeredImage& bdpt,
                                                    const std::vector<Partition>& partitions) {
    size_t pixels = size_t(bdpt.combined.width) * size_t(bdpt.combined.height);
    std::vector<std::vector<float>> out(partitions.size(), std::vector<float>(pixels, 0.0f));
    for (const ImageLayer& layer : bdpt.layers) {
        PathType t;
        EXPECT_TRUE(PathType::parse(layer.name, t)) << "the reference dropped types";
        for (size_t g = 0; g < partitions.size(); ++g)
            if (partitions[g].holds(t))
                for (size_t i = 0; i < pixels; ++i)
                    out[g][i] += luminance(
                        layer.image.at(int(i) % layer.image.width, int(i) / layer.image.width));
    }
    return out;
}

/// A pre-pass's per-partition images, raw and denoised, and a BDPT reference of each partition.
struct GuideImages {
    std::vector<Partition> partitions;
    std::vector<std::vector<float>> raw, denoised, references;
};

GuideImages guideImages(const RenderScene& scene, int width, int height, uint64_t samples,
                        double referenceSpp, int k = 10, uint64_t seed = 1) {
    GuideRun run(scene, width, height, 8);
    PrepassRun pre = prepassOf(run, samples, k, seed);
    GuideImages out;
    out.partitions = pre.partitions;
    out.raw = partitionPrepassImages(pre.prepass, pre.partitions, width, height);
    out.denoised = denoisePartitions(run.gbuffer(), out.raw, {}, &run.pool);
    RenderSettings st = run.settings;
    st.budget = referenceSpp;
    st.budgetKind = BudgetKind::SamplesPerPixel;
    st.seed = seed + 1000;
    out.references = partitionReferences(test::renderWith(scene, "bdpt", st).image, pre.partitions);
    return out;
}

struct AgreementRow {
    std::string label;
    double b = 0, referenceSupport = 0;
    SupportAgreement raw, denoised;
    /// The same with the reference thresholded at epsilon too (reference > epsilon counts as
    /// non-zero): whether D_i > epsilon where the partition's true image is.
    SupportAgreement rawAtEpsilon, denoisedAtEpsilon;
};

/// The thresholded D_i (and, for comparison, the undenoised images) against the references.
std::vector<AgreementRow> thresholdAgreement(const GuideImages& images, float epsilon) {
    std::vector<AgreementRow> rows;
    for (size_t p = 0; p < images.partitions.size(); ++p) {
        AgreementRow r;
        r.label = images.partitions[p].label;
        r.b = images.partitions[p].b;
        r.raw = supportAgreement(images.raw[p], images.references[p], epsilon);
        r.denoised = supportAgreement(images.denoised[p], images.references[p], epsilon);
        r.rawAtEpsilon = supportAgreement(images.raw[p], images.references[p], epsilon, epsilon);
        r.denoisedAtEpsilon =
            supportAgreement(images.denoised[p], images.references[p], epsilon, epsilon);
        r.referenceSupport =
            double(r.denoised.referenceNonzero) / double(images.references[p].size());
        rows.push_back(r);
    }
    return rows;
}

void printAgreement(const std::vector<AgreementRow>& rows, float epsilon) {
    std::printf(
        "epsilon %g: fraction of the reference's non-zero pixels with D > eps (nz) and of its "
        "zero pixels with D <= eps (z); the same with the reference thresholded at eps\n"
        "%-12s %10s %6s | %6s %6s | %6s %6s || %6s %6s | %6s %6s\n",
        double(epsilon), "partition", "b", "ref>0", "raw nz", "z", "D nz", "z", "raw nz", "z",
        "D nz", "z");
    for (const AgreementRow& r : rows)
        std::printf("%-12s %10.4g %6.3f | %6.3f %6.3f | %6.3f %6.3f || %6.3f %6.3f | %6.3f %6.3f\n",
                    r.label.c_str(), r.b, r.referenceSupport, r.raw.nonzeroAbove, r.raw.zeroBelow,
                    r.denoised.nonzeroAbove, r.denoised.zeroBelow, r.rawAtEpsilon.nonzeroAbove,
                    r.rawAtEpsilon.zeroBelow, r.denoisedAtEpsilon.nonzeroAbove,
                    r.denoisedAtEpsilon.zeroBelow);
}

TEST(Denoise, ThresholdMatchesTheReferenceSupportOnCornellGlass) {
    RenderScene scene = loadScene("cornell-glass");
    const float epsilon = 0.01f;
    GuideImages images = guideImages(scene, 48, 36, 20000, 32, 5);
    std::vector<AgreementRow> rows = thresholdAgreement(images, epsilon);
    printAgreement(rows, epsilon);
    ASSERT_GE(rows.size(), 4u);
    // Over all partitions: of the pixels where a partition's reference exceeds epsilon, the
    // share its D_i keeps above epsilon, raw and denoised; and the reference's zeros kept.
    double raw = 0, denoised = 0, total = 0;
    for (const AgreementRow& r : rows) {
        double n = double(r.denoisedAtEpsilon.referenceNonzero);
        total += n;
        raw += r.rawAtEpsilon.nonzeroAbove * n;
        denoised += r.denoisedAtEpsilon.nonzeroAbove * n;
        EXPECT_GE(r.denoised.zeroBelow, 0.97) << r.label << ": the support leaks";
    }
    std::printf("reference > epsilon kept: raw %.3f, denoised %.3f of %.0f pixels\n", raw / total,
                denoised / total, total);
    // Measured: raw 0.69, denoised 0.92 (of 3555 pixel-partitions); every zeroBelow >= 0.98.
    // The requirement (Eq. 17 needs V' = 1 on most of the support): 85% kept.
    EXPECT_GT(denoised / total, 0.85);
    // And the denoiser is why: its share beats the raw images' by more than a two-proportion
    // test's 3.29 standard errors (two-sided 1e-3) over these pixel-partitions.
    double pRaw = raw / total, pDenoised = denoised / total;
    double se = std::sqrt((pRaw * (1 - pRaw) + pDenoised * (1 - pDenoised)) / total);
    EXPECT_GT(pDenoised - pRaw, 3.29 * se) << "raw " << pRaw << ", denoised " << pDenoised;
}

/// The figures of the report (docs/guide-buffers.md): cornell-glass at the pre-pass density of the
/// default 10^5 samples at 1280x720, on a smaller image. Run by hand:
/// partita-tests --gtest_also_run_disabled_tests --gtest_filter='*ReportThreshold*'
/// (PARTITA_GUIDE_REPORT="width height samples referenceSpp" overrides the defaults).
TEST(Denoise, DISABLED_ReportThresholdAgreementOnCornellGlass) {
    int width = 160, height = 120;
    uint64_t samples = 100000ull * 160 * 120 / (1280 * 720);
    double spp = 256;
    if (const char* e = std::getenv("PARTITA_GUIDE_REPORT")) {
        unsigned long long s = 0;
        if (std::sscanf(e, "%d %d %llu %lf", &width, &height, &s, &spp) == 4) samples = s;
    }
    std::printf(
        "cornell-glass %dx%d, pre-pass %llu samples (%.3f a pixel), bdpt reference %g spp\n", width,
        height, (unsigned long long)samples, double(samples) / (double(width) * height), spp);
    RenderScene scene = loadScene("cornell-glass");
    GuideImages images = guideImages(scene, width, height, samples, spp);
    for (float epsilon : {0.001f, 0.01f, 0.1f})
        printAgreement(thresholdAgreement(images, epsilon), epsilon);
}

}  // namespace
}  // namespace partita
