// The shared path representation (core/path): on random BDPT paths, the densities a connection
// computed agree with the ones recomputed from the vertices alone, the MIS weights of every
// strategy that can sample a path sum to one, every strategy's f / p equals f(x) computed from
// the vertices over the product of its densities, and a path survives serialisation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "camera.h"
#include "environment_map.h"
#include "gltf/gltf_loader.h"
#include "integrators/pt/pt_integrator.h"
#include "path/connection.h"
#include "path/mis.h"
#include "path/path.h"
#include "path/random_walk.h"
#include "path/short_edge_damping.h"
#include "render_scene.h"
#include "renderer.h"
#include "scene_builders.h"

namespace partita {
namespace {

struct PathFixture {
    RenderScene scene;
    Camera camera;
    explicit PathFixture(SceneData data)
        : scene(std::move(data)), camera(resolveCamera(scene.data(), ""), 32, 24) {}
};

/// Calls check(path, densities, info, sample, s, t) for every valid strategy of `samples`
/// random subpath pairs, Russian roulette off (so f / p is exactly a product of densities).
template <typename Check>
int forEachStrategy(PathFixture& f, int samples, Check&& check) {
    WalkSettings walk;
    walk.maxVertices = 7;
    walk.rouletteStartDepth = 1000;
    Connector connector(f.scene, f.camera, /*keepPaths=*/true);
    std::vector<PathVertex> cam, light;
    int checked = 0;
    for (int i = 0; i < samples; ++i) {
        Rng rng(77, uint64_t(i));
        uint64_t rays = 0;
        Vec2f raster{rng.nextFloat() * 32, rng.nextFloat() * 24};
        traceCameraSubpath(f.scene, f.camera, f.camera.generateRay(raster), rng, walk, cam, rays);
        traceLightSubpath(f.scene, rng, walk, light, rays);
        for (int t = 1; t <= int(cam.size()); ++t)
            for (int s = 0; s <= std::max(int(light.size()), 1); ++s) {
                if (s > int(light.size()) && !(s == 1 && t > 1)) continue;
                StrategySample c = connector.connect(cam, light, s, t, rng, rays);
                if (!c.valid) continue;
                ++checked;
                check(connector.lastPath(), connector.lastDensities(), connector.lastPathInfo(), c,
                      s, t);
            }
    }
    return checked;
}

/// The walks trace rays from origins offset off the surface (ray.h), so a direction, and the
/// cosines and densities from it, recomputed from the vertex positions differs from the sampled
/// one by the offset over the edge length: about 1e-3 relative on the shipped scenes' scale, more
/// at grazing angles. Not statistics: a float-geometry bound.
constexpr float kOffsetTolerance = 1e-2f;

/// Whether the offsets are small against the path's geometry: no edge shorter than 5 cm (the
/// scenes are metres across) and no grazing geometric cosine, where the bound above holds.
bool wellConditioned(const std::vector<PathVertex>& path) {
    for (size_t i = 0; i + 1 < path.size(); ++i) {
        Vec3f d = path[i + 1].p - path[i].p;
        float len = length(d);
        if (len < 0.05f) return false;
        Vec3f w = d / len;
        if (geometricCos(path[i], w) < 0.05f || geometricCos(path[i + 1], w) < 0.05f) return false;
    }
    return true;
}

bool relativelyClose(double a, double b, double tol) {
    return std::abs(a - b) <= tol * std::max(std::abs(a), std::abs(b)) + 1e-30;
}

void checkPaths(SceneData data, bool expectDirac = true) {
    PathFixture f(std::move(data));
    int withDelta = 0, compared = 0;
    int checked = forEachStrategy(
        f, 400,
        [&](const std::vector<PathVertex>& path, const std::vector<VertexDensities>& d,
            MisPathInfo info, const StrategySample& c, int s, int t) {
            SCOPED_TRACE("s=" + std::to_string(s) + " t=" + std::to_string(t));
            if (!wellConditioned(path)) return;
            // The cached densities are the recomputed ones.
            EXPECT_EQ(verifyPath(f.scene, f.camera, path, kOffsetTolerance), "");
            EXPECT_EQ(pathType(path), c.type);
            // MIS: the weights of all strategies that can sample this path sum to one.
            double sum = 0;
            for (int k = 0; k <= int(path.size()); ++k)
                if (strategyCanSample(d, k, info)) sum += misWeight(d, k, info);
            EXPECT_TRUE(strategyCanSample(d, t, info));
            EXPECT_NEAR(sum, 1.0, 1e-4);
            // f / p: the connection's value against f(x) over the strategy's own density, with
            // Dirac vertices as their branch's coefficient and probability (dirac_vertex.h).
            bool dirac = false;
            for (const PathVertex& v : path) dirac |= v.isSurface() && v.delta;
            std::vector<VertexDensities> exact =
                recomputeDensities(f.scene, f.camera, path, DiracVertices::Coefficient);
            double p = 1;
            for (int i = 1; i < int(path.size()); ++i)
                p *= i < t ? exact[size_t(i)].fromEye : exact[size_t(i)].fromLight;
            Rgb fx = pathContribution(f.scene, f.camera, path, DiracVertices::Coefficient);
            for (int k = 0; k < 3; ++k)
                EXPECT_TRUE(relativelyClose(c.value[k], fx[k] / p, kOffsetTolerance))
                    << "channel " << k << ": " << c.value[k] << " vs " << fx[k] / p;
            ++compared;
            withDelta += dirac;
        });
    EXPECT_GT(checked, 200);
    EXPECT_GT(compared, 100);
    if (expectDirac) {
        EXPECT_GT(withDelta, 50);
    }
}

TEST(PathRepresentation, DensitiesWeightsAndContributionsOnCornell) {
    checkPaths(loadGltfFile(std::string(PARTITA_SCENES_DIR) + "/cornell/cornell.gltf"),
               /*expectDirac=*/false);
}

TEST(PathRepresentation, DensitiesWeightsAndContributionsWithSpecularVertices) {
    checkPaths(test::specularBoxScene());
}

TEST(PathRepresentation, DensitiesWeightsAndContributionsThroughAbsorbingMedia) {
    // A tinted glass sphere and a tinted glass box: f(x) must carry the edges' transmittance.
    SceneData s = test::specularBoxScene();
    s.materials[3].hasVolume = true;
    s.materials[3].attenuationColor = Rgb(0.2f, 0.5f, 0.9f);
    s.materials[3].attenuationDistance = 0.3f;
    s.meshes.push_back(test::box({-0.2f, 0.8f, -0.6f}, {0.3f, 1.3f, -0.1f}, 3, false));
    checkPaths(std::move(s));
}

TEST(PathRepresentation, DensitiesWeightsAndContributionsWithPunctualLightsAndEnvironment) {
    SceneData s = test::specularBoxScene();
    PunctualLightDesc point;
    point.type = PunctualLightDesc::Type::Point;
    point.intensity = 2;
    point.position = {0.3f, 1.5f, 0.2f};
    PunctualLightDesc spot = point;
    spot.type = PunctualLightDesc::Type::Spot;
    spot.position = {-0.5f, 1.8f, -0.3f};
    spot.direction = {0, -1, 0};
    spot.outerConeAngle = 0.8f;
    PunctualLightDesc sun = point;
    sun.type = PunctualLightDesc::Type::Directional;
    sun.direction = normalize(Vec3f(0.2f, -1, 0.1f));
    s.lights = {point, spot, sun};
    // A hole in the ceiling lets the directional light in.
    s.meshes[0] = test::box({-1, 0, -1}, {1, 2, 1}, 0, true);
    s.meshes[0].indices.resize(s.meshes[0].indices.size() - 6);  // drop the +y face
    checkPaths(s);
    // And the environment, seen through the same hole.
    Image sky(16, 8);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x)
            sky.set(x, y, Rgb(0.2f + 0.1f * float(x), 0.5f, 1.0f / (1 + y)));
    s.environment = std::make_shared<EnvironmentMap>(std::move(sky), 30.0f);
    checkPaths(std::move(s));
}

TEST(PathRepresentation, SerialisedPathRebuildsExactly) {
    PathFixture f(test::specularBoxScene());
    int roundTrips = 0;
    forEachStrategy(f, 50,
                    [&](const std::vector<PathVertex>& path, const std::vector<VertexDensities>&,
                        MisPathInfo, const StrategySample&, int, int) {
                        std::vector<uint8_t> bytes = serializePath(path);
                        EXPECT_EQ(bytes.size(), 32 * path.size());
                        std::vector<PathVertex> back = deserializePath(f.scene, f.camera, bytes);
                        ASSERT_EQ(back.size(), path.size());
                        for (size_t i = 0; i < path.size(); ++i) {
                            EXPECT_EQ(back[i].p, path[i].p) << i;
                            EXPECT_EQ(back[i].delta, path[i].delta) << i;
                            EXPECT_EQ(back[i].light, path[i].light) << i;
                        }
                        EXPECT_EQ(pathType(back), pathType(path));
                        EXPECT_EQ(verifyPath(f.scene, f.camera, back, kOffsetTolerance), "");
                        Rgb a = pathContribution(f.scene, f.camera, path),
                            b = pathContribution(f.scene, f.camera, back);
                        EXPECT_EQ(a, b);
                        ++roundTrips;
                    });
    EXPECT_GT(roundTrips, 20);
    std::vector<uint8_t> garbage(64, 0xab);
    EXPECT_THROW(deserializePath(f.scene, f.camera, garbage), std::invalid_argument);
    EXPECT_THROW(deserializePath(f.scene, f.camera, std::vector<uint8_t>(5)),
                 std::invalid_argument);
}

// Found by tests/fuzz/fuzz_chain_plan: a chain plan from a shared volume whose path names a mesh
// or triangle the scene lacks threw std::out_of_range, which deserializePath's callers (shard
// renders) do not expect; a non-finite point went on into the densities.
TEST(PathRepresentation, ASerialisedPathNamingNoSuchTriangleOrNoPointIsRefused) {
    PathFixture f(test::specularBoxScene());
    std::vector<uint8_t> good;
    forEachStrategy(f, 50,
                    [&](const std::vector<PathVertex>& path, const std::vector<VertexDensities>&,
                        MisPathInfo, const StrategySample&, int, int) {
                        if (good.empty() && path.size() >= 3) good = serializePath(path);
                    });
    ASSERT_FALSE(good.empty());
    ASSERT_NO_THROW(deserializePath(f.scene, f.camera, good));
    // Vertex 1 is a surface vertex: fields at offsets 8 (mesh), 12 (triangle), 16 (a).
    auto withField = [&](size_t offset, uint32_t value) {
        std::vector<uint8_t> bytes = good;
        std::memcpy(bytes.data() + 32 + offset, &value, 4);
        return bytes;
    };
    const float nan = std::nanf("");
    uint32_t nanBits;
    std::memcpy(&nanBits, &nan, 4);
    for (const auto& bytes : {withField(8, 1000), withField(12, 1u << 30), withField(16, nanBits)})
        EXPECT_THROW(deserializePath(f.scene, f.camera, bytes), std::invalid_argument);
}

TEST(ShortEdgeDamping, MultipliesSquaredLengthsOverEpsBelowIt) {
    // eps 1: edges of 0.5, 2 and 0.1 give 0.25 x 1 x 0.01; eps 0 damps nothing.
    ShortEdgeDamping damping(1.0f);
    for (Vec3f p : {Vec3f(0, 0, 0), Vec3f(0.5f, 0, 0), Vec3f(2.5f, 0, 0), Vec3f(2.6f, 0, 0)})
        damping.add(p);
    EXPECT_NEAR(damping.factor(), 0.25 * 0.01, 1e-6);
    ShortEdgeDamping none(0.0f);
    none.add(Vec3f(0, 0, 0));
    none.add(Vec3f(1e-6f, 0, 0));
    EXPECT_EQ(none.factor(), 1.0f);
}

}  // namespace
}  // namespace partita
