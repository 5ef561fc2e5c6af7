// glTF loading: containers and resources, node hierarchy, primitive topology, accessors.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "gltf/gltf_meshes.h"

#include "gltf_test_helpers.h"

namespace partita {
namespace {

using namespace gltftest;

void expectNear(Vec3f a, Vec3f b, float eps = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, eps);
    EXPECT_NEAR(a.y, b.y, eps);
    EXPECT_NEAR(a.z, b.z, eps);
}

Vec3f geometricNormal(const TriangleMesh& m, size_t t) {
    Vec3f a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
          c = m.positions[m.indices[3 * t + 2]];
    return normalize(cross(b - a, c - a));
}

bool hasWarning(const SceneData& s, const std::string& text) {
    for (const auto& w : s.warnings)
        if (w.find(text) != std::string::npos) return true;
    return false;
}

// ---- containers and resources ----

TEST(GltfLoader, LoadsGltfWithDataUriBuffer) {
    SceneData s = loadJson(quadScene().embedded());
    ASSERT_EQ(s.meshes.size(), 1u);
    const TriangleMesh& m = s.meshes[0];
    EXPECT_EQ(m.positions.size(), 4u);
    EXPECT_EQ(m.triangleCount(), 2u);
    EXPECT_EQ(m.normals.size(), 4u);
    EXPECT_EQ(m.uvs[0].size(), 4u);
    EXPECT_TRUE(m.uvs[1].empty());
    EXPECT_EQ(m.material, -1);
    expectNear(m.positions[2], {1, 1, 0});
    expectNear(m.normals[0], {0, 0, 1});
}

TEST(GltfLoader, LoadsGltfWithExternalBinFromItsFolder) {
    TempDir dir;
    GltfBuilder b = quadScene();
    dir.write("scene.bin", b.bin);
    auto file = dir.write("scene.gltf", textBytes(b.external("scene.bin").dump()));
    SceneData s = loadGltfFile(file);
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.meshes[0].triangleCount(), 2u);
}

TEST(GltfLoader, LoadsGlbFileAndGlbBytes) {
    TempDir dir;
    std::vector<uint8_t> glb = quadScene().glb();
    SceneData fromFile = loadGltfFile(dir.write("scene.glb", glb));
    ASSERT_EQ(fromFile.meshes.size(), 1u);
    EXPECT_EQ(fromFile.meshes[0].triangleCount(), 2u);
    SceneData fromMemory = loadGltfMemory(glb, true, MemoryResolver({}));
    EXPECT_EQ(fromMemory.meshes[0].positions.size(), 4u);
}

TEST(GltfLoader, GlbWithoutBinChunkButDataUriBuffer) {
    std::vector<uint8_t> glb = makeGlb(quadScene().embedded().dump(), {});
    SceneData s = loadGltfMemory(glb, true, MemoryResolver({}));
    EXPECT_EQ(s.meshes.size(), 1u);
}

TEST(GltfLoader, MemoryResolverServesUploadedResources) {
    GltfBuilder b = quadScene();
    SceneData s = loadJson(b.external("data/quad.bin"), {{"data/quad.bin", b.bin}});
    EXPECT_EQ(s.meshes.size(), 1u);
    // "./" names the same upload.
    SceneData s2 = loadJson(b.external("./data/quad.bin"), {{"data/quad.bin", b.bin}});
    EXPECT_EQ(s2.meshes.size(), 1u);
}

TEST(GltfLoader, PercentEncodedUriIsDecoded) {
    TempDir dir;
    GltfBuilder b = quadScene();
    dir.write("my scene.bin", b.bin);
    auto file = dir.write("scene.gltf", textBytes(b.external("my%20scene.bin").dump()));
    EXPECT_EQ(loadGltfFile(file).meshes.size(), 1u);
}

#ifdef PARTITA_SCENES_DIR
TEST(GltfLoader, LoadsEveryShippedScene) {
    namespace fs = std::filesystem;
    fs::path dir = PARTITA_SCENES_DIR;
    int count = 0;
    if (fs::exists(dir)) {
        for (const auto& entry : fs::recursive_directory_iterator(dir)) {
            fs::path ext = entry.path().extension();
            if (ext != ".gltf" && ext != ".glb") continue;
            SCOPED_TRACE(entry.path().string());
            SceneData s = loadGltfFile(entry.path());
            EXPECT_FALSE(s.meshes.empty());
            EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
            ++count;
        }
    }
    if (count == 0) GTEST_SKIP() << "no shipped scenes in " << dir;
}
#endif

// ---- node hierarchy ----

SceneData loadQuadWithNode(const json& nodeProps) {
    return loadJson(quadScene(nodeProps).embedded());
}

TEST(GltfNodes, TranslationRotationScale) {
    // Scale x by 2, rotate 90 degrees about +Z, translate by (10, 0, 0): (1,0,0) -> (0,2,0) ->
    // (10,2,0).
    float h = std::sqrt(0.5f);
    SceneData s = loadQuadWithNode(
        {{"translation", {10, 0, 0}}, {"rotation", {0, 0, h, h}}, {"scale", {2, 1, 1}}});
    const TriangleMesh& m = s.meshes[0];
    expectNear(m.positions[1], {10, 2, 0});
    expectNear(m.positions[3], {9, 0, 0});  // (0,1,0) rotates to (-1,0,0)
    expectNear(m.normals[0], {0, 0, 1});
}

TEST(GltfNodes, NonUnitQuaternionIsNormalised) {
    SceneData s = loadQuadWithNode({{"rotation", {0, 0, 2, 2}}});
    expectNear(s.meshes[0].positions[1], {0, 1, 0});
}

TEST(GltfNodes, MatrixTransform) {
    // Column-major: translation (1, 2, 3), uniform scale 3.
    SceneData s = loadQuadWithNode({{"matrix", {3, 0, 0, 0, 0, 3, 0, 0, 0, 0, 3, 0, 1, 2, 3, 1}}});
    expectNear(s.meshes[0].positions[2], {4, 5, 3});
}

TEST(GltfNodes, ChildComposesWithParent) {
    GltfBuilder b;
    int mesh = b.mesh(json::array({quadPrimitive(b, true)}));
    int child = b.node({{"mesh", mesh}, {"translation", {0, 0, 5}}});
    int parent = b.node({{"children", {child}}, {"scale", {2, 2, 2}}});
    b.scene({parent});
    SceneData s = loadJson(b.embedded());
    ASSERT_EQ(s.meshes.size(), 1u);
    expectNear(s.meshes[0].positions[2], {2, 2, 10});
}

TEST(GltfNodes, UsesTheDefaultSceneAndAllItsRoots) {
    GltfBuilder b;
    int mesh = b.mesh(json::array({quadPrimitive(b)}));
    int a = b.node({{"mesh", mesh}, {"translation", {100, 0, 0}}});
    int c = b.node({{"mesh", mesh}, {"translation", {0, 100, 0}}});
    int d = b.node({{"mesh", mesh}, {"translation", {0, 0, 100}}});
    b.doc["scenes"] = json::array({{{"nodes", {a}}}, {{"nodes", {c, d}}}});
    b.doc["scene"] = 1;
    SceneData s = loadJson(b.embedded());
    ASSERT_EQ(s.meshes.size(), 2u);
    EXPECT_NEAR(s.meshes[0].positions[0].y, 100, 1e-4);
    EXPECT_NEAR(s.meshes[1].positions[0].z, 100, 1e-4);

    b.doc.erase("scene");  // no default: scene 0
    SceneData s0 = loadJson(b.embedded());
    ASSERT_EQ(s0.meshes.size(), 1u);
    EXPECT_NEAR(s0.meshes[0].positions[0].x, 100, 1e-4);
}

TEST(GltfNodes, FileWithoutScenesUsesRootNodesWithWarning) {
    GltfBuilder b;
    int mesh = b.mesh(json::array({quadPrimitive(b)}));
    int child = b.node({{"mesh", mesh}});
    b.node({{"children", {child}}});
    SceneData s = loadJson(b.embedded());
    EXPECT_EQ(s.meshes.size(), 1u);
    EXPECT_TRUE(hasWarning(s, "no scenes"));
}

TEST(GltfNodes, MeshInstancedByTwoNodesIsDuplicatedInWorldSpace) {
    GltfBuilder b;
    int mesh = b.mesh(json::array({quadPrimitive(b, true)}));
    int n0 = b.node({{"mesh", mesh}, {"name", "left"}});
    int n1 = b.node({{"mesh", mesh}, {"name", "right"}, {"translation", {5, 0, 0}}});
    b.scene({n0, n1});
    SceneData s = loadJson(b.embedded());
    ASSERT_EQ(s.meshes.size(), 2u);
    EXPECT_EQ(s.meshes[0].name, "left");
    EXPECT_EQ(s.meshes[1].name, "right");
    expectNear(s.meshes[0].positions[1], {1, 0, 0});
    expectNear(s.meshes[1].positions[1], {6, 0, 0});
}

TEST(GltfNodes, NormalsUseTheInverseTranspose) {
    // A 45-degree slope in x-z with normal (-1, 0, 1)/sqrt2; scaling x by 2 makes the slope
    // shallower, so the true normal is (-1, 0, 2)/sqrt5 (inverse transpose), not (-2, 0, 1).
    GltfBuilder b;
    json prim = {{"attributes",
                  {{"POSITION", b.floats({0, 0, 0, 1, 0, 1, 0, 1, 0}, "VEC3")},
                   {"NORMAL", b.floats({-1, 0, 1, -1, 0, 1, -1, 0, 1}, "VEC3")}}}};
    b.scene({b.node({{"mesh", b.mesh(json::array({prim}))}, {"scale", {2, 1, 1}}})});
    SceneData s = loadJson(b.embedded());
    float r5 = 1 / std::sqrt(5.f);
    expectNear(s.meshes[0].normals[0], {-r5, 0, 2 * r5});
}

TEST(GltfNodes, NegativeDeterminantFlipsWinding) {
    SceneData plain = loadQuadWithNode(json::object());
    SceneData mirrored = loadQuadWithNode({{"scale", {1, 1, -1}}});
    // The mirror turns the file normal (0,0,1) into (0,0,-1); the flipped winding keeps the
    // geometric normal on the same side as the shading normal.
    const TriangleMesh& m = mirrored.meshes[0];
    expectNear(m.normals[0], {0, 0, -1});
    expectNear(geometricNormal(m, 0), {0, 0, -1});
    expectNear(geometricNormal(plain.meshes[0], 0), {0, 0, 1});
}

TEST(GltfNodes, ZeroScaleNodeIsSkippedWithWarning) {
    GltfBuilder b;
    int mesh = b.mesh(json::array({quadPrimitive(b)}));
    int n0 = b.node({{"mesh", mesh}});
    int n1 = b.node({{"mesh", mesh}, {"scale", {0, 0, 0}}});
    int n2 = b.node({{"mesh", mesh}, {"matrix", {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1}}});
    b.scene({n0, n1, n2});
    SceneData s = loadJson(b.embedded());
    EXPECT_EQ(s.meshes.size(), 1u);
    EXPECT_TRUE(hasWarning(s, "zero scale"));
}

// ---- topology ----

SceneData loadPrimitive(const std::function<json(GltfBuilder&)>& make) {
    GltfBuilder b;
    b.scene({b.node({{"mesh", b.mesh(json::array({make(b)}))}})});
    return loadJson(b.embedded());
}

const std::vector<float> kFivePoints = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0};

TEST(GltfTopology, TriangleStrip) {
    SceneData s = loadPrimitive([](GltfBuilder& b) {
        return json{{"attributes", {{"POSITION", b.floats(kFivePoints, "VEC3")}}}, {"mode", 5}};
    });
    // Unwelded flat normals: 3 triangles; all face +Z thanks to the alternating order.
    const TriangleMesh& m = s.meshes[0];
    ASSERT_EQ(m.triangleCount(), 3u);
    for (size_t t = 0; t < 3; ++t) expectNear(geometricNormal(m, t), {0, 0, 1});
    expectNear(m.normals[0], {0, 0, 1});
}

TEST(GltfTopology, TriangleFanAndAssemblyOrder) {
    EXPECT_EQ(gltf::assembleTriangles(6, {0, 1, 2, 3}), (std::vector<uint32_t>{1, 2, 0, 2, 3, 0}));
    EXPECT_EQ(gltf::assembleTriangles(5, {0, 1, 2, 3}), (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
    // A repeated index (strip restart) makes a degenerate triangle, which is dropped.
    EXPECT_EQ(gltf::assembleTriangles(5, {0, 1, 1, 2}), (std::vector<uint32_t>{}));
    SceneData s = loadPrimitive([](GltfBuilder& b) {
        return json{
            {"attributes", {{"POSITION", b.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3")}}},
            {"indices", b.indices<uint8_t>({0, 1, 2, 3})},
            {"mode", 6}};
    });
    ASSERT_EQ(s.meshes[0].triangleCount(), 2u);
    expectNear(geometricNormal(s.meshes[0], 1), {0, 0, 1});
}

TEST(GltfTopology, IndexComponentTypesAndNonIndexed) {
    auto withIndices = [](const std::function<int(GltfBuilder&)>& indices) {
        return loadPrimitive([&](GltfBuilder& b) {
            json p = {{"attributes",
                       {{"POSITION", b.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3")}}}};
            if (indices) p["indices"] = indices(b);
            return p;
        });
    };
    SceneData u8 = withIndices([](GltfBuilder& b) {
        return b.indices<uint8_t>({0, 1, 2, 0, 2, 3});
    });
    SceneData u16 = withIndices([](GltfBuilder& b) {
        return b.indices<uint16_t>({0, 1, 2, 0, 2, 3});
    });
    SceneData u32 = withIndices([](GltfBuilder& b) {
        return b.indices<uint32_t>({0, 1, 2, 0, 2, 3});
    });
    SceneData none = withIndices(nullptr);
    EXPECT_EQ(u8.meshes[0].triangleCount(), 2u);
    EXPECT_EQ(u16.meshes[0].triangleCount(), 2u);
    EXPECT_EQ(u32.meshes[0].triangleCount(), 2u);
    EXPECT_EQ(none.meshes[0].triangleCount(), 1u);  // 4 vertices: one triangle + a warning
    EXPECT_TRUE(hasWarning(none, "multiple of 3"));
}

TEST(GltfTopology, PointsAndLinesAreSkippedWithWarning) {
    GltfBuilder b;
    json points = {{"attributes", {{"POSITION", b.floats(kFivePoints, "VEC3")}}}, {"mode", 0}};
    json lines = {{"attributes", {{"POSITION", b.floats(kFivePoints, "VEC3")}}}, {"mode", 1}};
    b.scene({b.node({{"mesh", b.mesh(json::array({points, lines, quadPrimitive(b)}))}})});
    SceneData s = loadJson(b.embedded());
    EXPECT_EQ(s.meshes.size(), 1u);
    EXPECT_TRUE(hasWarning(s, "points and lines"));
}

TEST(GltfTopology, UnreferencedVerticesAreDroppedAndEmptyPrimitivesSkipped) {
    GltfBuilder b;
    json used = {{"attributes",
                  {{"POSITION", b.floats({0, 0, 0, 9, 9, 9, 1, 0, 0, 8, 8, 8, 0, 1, 0}, "VEC3")},
                   {"NORMAL", b.floats({0, 0, 1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1}, "VEC3")}}},
                 {"indices", b.indices<uint8_t>({0, 2, 4})}};
    json degenerate = {{"attributes", {{"POSITION", b.floats(kFivePoints, "VEC3")}}},
                       {"indices", b.indices<uint8_t>({0, 1, 1, 2, 2, 2})}};
    b.scene({b.node({{"mesh", b.mesh(json::array({used, degenerate}))}})});
    SceneData s = loadJson(b.embedded());
    ASSERT_EQ(s.meshes.size(), 1u);
    const TriangleMesh& m = s.meshes[0];
    EXPECT_EQ(m.positions.size(), 3u);
    EXPECT_EQ(m.normals.size(), 3u);
    EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2}));
    expectNear(m.positions[1], {1, 0, 0});
    EXPECT_TRUE(hasWarning(s, "no non-degenerate triangles"));
}

// ---- normals ----

TEST(GltfNormals, FlatNormalsByUnweldingWhenAbsent) {
    SceneData s = loadPrimitive([](GltfBuilder& b) { return quadPrimitive(b, false, true); });
    const TriangleMesh& m = s.meshes[0];
    EXPECT_EQ(m.positions.size(), 6u);
    EXPECT_EQ(m.normals.size(), 6u);
    EXPECT_EQ(m.uvs[0].size(), 6u);
    for (Vec3f n : m.normals) expectNear(n, {0, 0, 1});
    EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5}));
}

TEST(GltfNormals, NormalsAreNormalisedAndDegenerateOnesReplaced) {
    SceneData s = loadPrimitive([](GltfBuilder& b) {
        return json{{"attributes",
                     {{"POSITION", b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3")},
                      {"NORMAL", b.floats({0, 0, 5, 0, 0, 0, NAN, 0, 1}, "VEC3")}}}};
    });
    for (Vec3f n : s.meshes[0].normals) expectNear(n, {0, 0, 1});
}

// ---- accessors ----

TEST(GltfAccessors, NormalizedTexcoordTypes) {
    for (int ct : {kUByte, kUShort}) {
        SceneData s = loadPrimitive([ct](GltfBuilder& b) {
            std::vector<uint8_t> raw;
            if (ct == kUByte)
                raw = {0, 255, 0, 0, 255, 0, 0, 0, 51, 102, 0, 0};  // stride 4 (padded)
            else
                raw = bytesOf(std::vector<uint16_t>{0, 65535, 65535, 0, 13107, 26214});
            int view = b.view(raw, ct == kUByte ? 4 : 0);
            json p = quadPrimitive(b);
            p["attributes"]["TEXCOORD_1"] = b.accessor(view, ct, 3, "VEC2", true);
            p["attributes"]["POSITION"] = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3");
            p.erase("indices");
            return p;
        });
        const auto& uv = s.meshes[0].uvs[1];
        ASSERT_EQ(uv.size(), 3u) << ct;  // unwelded: one per corner
        EXPECT_NEAR(uv[0].y, 1.0f, 1e-6);
        EXPECT_NEAR(uv[1].x, 1.0f, 1e-6);
        EXPECT_NEAR(uv[2].x, 0.2f, 1e-6);
        EXPECT_NEAR(uv[2].y, 0.4f, 1e-6);
    }
}

TEST(GltfAccessors, FloatTexcoordAndBothSets) {
    SceneData s = loadPrimitive([](GltfBuilder& b) {
        json p = quadPrimitive(b, true, true);
        p["attributes"]["TEXCOORD_1"] = b.floats({0.5f, 0.5f, 1, 1, 2, 2, 3, 3}, "VEC2");
        return p;
    });
    EXPECT_NEAR(s.meshes[0].uvs[0][2].x, 1.0f, 1e-6);
    EXPECT_NEAR(s.meshes[0].uvs[1][3].y, 3.0f, 1e-6);
}

TEST(GltfAccessors, InterleavedByteStrideAndByteOffset) {
    // Per vertex: position (3 floats) then texcoord (2 floats), stride 20, after an 8-byte header.
    std::vector<float> interleaved = {0,    0,    0, 0.1f, 0.2f, 1,    0,   0,
                                      0.3f, 0.4f, 0, 1,    0,    0.5f, 0.6f};
    std::vector<uint8_t> raw(8, 0xAB);
    auto body = bytesOf(interleaved);
    raw.insert(raw.end(), body.begin(), body.end());
    SceneData s = loadPrimitive([&](GltfBuilder& b) {
        int view = b.view(raw, 20);
        return json{{"attributes",
                     {{"POSITION", b.accessor(view, kFloat, 3, "VEC3", false, 8)},
                      {"TEXCOORD_0", b.accessor(view, kFloat, 3, "VEC2", false, 20)}}}};
    });
    const TriangleMesh& m = s.meshes[0];  // unwelded in vertex order
    expectNear(m.positions[1], {1, 0, 0});
    expectNear(m.positions[2], {0, 1, 0});
    EXPECT_NEAR(m.uvs[0][0].y, 0.2f, 1e-6);
    EXPECT_NEAR(m.uvs[0][2].x, 0.5f, 1e-6);
    EXPECT_NEAR(m.uvs[0][2].y, 0.6f, 1e-6);
}

TEST(GltfAccessors, QuantizedPositionsAndNormals) {
    // KHR_mesh_quantization: SHORT positions (not normalised), normalised BYTE normals.
    SceneData s = loadPrimitive([](GltfBuilder& b) {
        int pv = b.view(bytesOf(std::vector<int16_t>{0, 0, 0, 0, 300, 0, 0, 0, 0, 300, 0, 0}), 8);
        int nv = b.view({0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127, 0}, 4);
        return json{{"attributes",
                     {{"POSITION", b.accessor(pv, kShort, 3, "VEC3")},
                      {"NORMAL", b.accessor(nv, kByte, 3, "VEC3", true)}}}};
    });
    expectNear(s.meshes[0].positions[1], {300, 0, 0});
    expectNear(s.meshes[0].normals[2], {0, 0, 1});
}

TEST(GltfAccessors, SparseSubstitutionOverBufferView) {
    SceneData s = loadPrimitive([](GltfBuilder& b) {
        json p = {{"attributes", {{"POSITION", b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3")}}}};
        int pos = p["attributes"]["POSITION"];
        b.doc["accessors"][pos]["sparse"] = {
            {"count", 1},
            {"indices",
             {{"bufferView", b.view(bytesOf(std::vector<uint16_t>{2, 0}))},
              {"componentType", kUShort}}},
            {"values", {{"bufferView", b.view(bytesOf(std::vector<float>{0, 7, 0}))}}}};
        return p;
    });
    expectNear(s.meshes[0].positions[2], {0, 7, 0});
    expectNear(s.meshes[0].positions[1], {1, 0, 0});
}

TEST(GltfAccessors, SparseIndices) {
    // Indices {0, 1, 2, 0, 1, 2} with entry 4 replaced by 2 and entry 5 by 3: (0 1 2) (0 2 3).
    SceneData s = loadPrimitive([](GltfBuilder& b) {
        json p = quadPrimitive(b, true);
        p["indices"] = b.indices<uint16_t>({0, 1, 2, 0, 1, 2});
        int idx = p["indices"];
        b.doc["accessors"][idx]["sparse"] = {
            {"count", 2},
            {"indices", {{"bufferView", b.view({4, 5, 0, 0})}, {"componentType", kUByte}}},
            {"values", {{"bufferView", b.view(bytesOf(std::vector<uint16_t>{2, 3}))}}}};
        return p;
    });
    EXPECT_EQ(s.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}

TEST(GltfAccessors, SparseWithoutBufferViewStartsFromZeros) {
    SceneData s = loadPrimitive([](GltfBuilder& b) {
        int pos = b.accessor(-1, kFloat, 3, "VEC3");
        b.doc["accessors"][pos]["sparse"] = {
            {"count", 2},
            {"indices", {{"bufferView", b.view({1, 2, 0, 0})}, {"componentType", kUByte}}},
            {"values", {{"bufferView", b.view(bytesOf(std::vector<float>{1, 0, 0, 0, 1, 0}))}}}};
        return json{{"attributes", {{"POSITION", pos}}}};
    });
    const TriangleMesh& m = s.meshes[0];
    expectNear(m.positions[0], {0, 0, 0});
    expectNear(m.positions[1], {1, 0, 0});
    expectNear(m.positions[2], {0, 1, 0});
}

}  // namespace
}  // namespace partita
