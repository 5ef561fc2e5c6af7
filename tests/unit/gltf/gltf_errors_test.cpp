// Malformed glTF input: every case is a SceneLoadError with one line that names the problem.
#include <gtest/gtest.h>

#include <limits>

#include "gltf_test_helpers.h"

namespace partita {
namespace {

using namespace gltftest;

#define EXPECT_MENTIONS(error, text) \
    EXPECT_NE((error).find(text), std::string::npos) << "message: " << (error)

std::string bytesError(const std::vector<uint8_t>& bytes, bool isBinary,
                       const GltfLoadLimits& limits = {}) {
    return errorOf([&] { loadGltfMemory(bytes, isBinary, MemoryResolver({}), limits); });
}

std::string textError(const std::string& text) { return bytesError(textBytes(text), false); }

// ---- containers and JSON ----

TEST(GltfErrors, InvalidJson) {
    EXPECT_MENTIONS(textError("{\"asset\": {\"version\": "), "invalid JSON");
}

TEST(GltfErrors, JsonRootIsNotAnObject) {
    EXPECT_MENTIONS(textError("[1, 2, 3]"), "not an object");
}

TEST(GltfErrors, MissingAssetAndWrongVersion) {
    EXPECT_MENTIONS(textError("{\"nodes\": []}"), "asset");
    EXPECT_MENTIONS(textError("{\"asset\": {\"version\": \"1.0\"}}"), "version 1.0");
}

TEST(GltfErrors, DeeplyNestedJsonIsRefused) {
    std::string deep =
        "{\"asset\": {\"version\": \"2.0\"}, \"extras\": " + std::string(100000, '[') +
        std::string(100000, ']') + "}";
    EXPECT_MENTIONS(textError(deep), "nests deeper");
}

TEST(GltfErrors, TruncatedGlb) {
    std::vector<uint8_t> glb = quadScene().glb();
    std::vector<uint8_t> truncated(glb.begin(), glb.begin() + long(glb.size() / 2));
    EXPECT_MENTIONS(bytesError(truncated, true), "truncated");
    EXPECT_MENTIONS(bytesError({'g', 'l', 'T', 'F', 2, 0}, true), "truncated");
}

TEST(GltfErrors, GlbBadMagicAndVersion) {
    std::vector<uint8_t> glb = quadScene().glb();
    std::vector<uint8_t> badMagic = glb;
    badMagic[0] = 'x';
    EXPECT_MENTIONS(bytesError(badMagic, true), "magic");
    std::vector<uint8_t> badVersion = glb;
    badVersion[4] = 1;
    EXPECT_MENTIONS(bytesError(badVersion, true), "version 1");
}

TEST(GltfErrors, GlbChunkLengthsOutOfRange) {
    std::vector<uint8_t> glb = quadScene().glb();
    uint32_t jsonLength;
    std::memcpy(&jsonLength, &glb[12], 4);
    // BIN chunk declared 4 bytes longer than what follows it (tinygltf alone would read past
    // the end of the data here).
    std::vector<uint8_t> longBin = glb;
    uint32_t binLength;
    std::memcpy(&binLength, &longBin[20 + jsonLength], 4);
    binLength += 4;
    std::memcpy(&longBin[20 + jsonLength], &binLength, 4);
    EXPECT_MENTIONS(bytesError(longBin, true), "BIN chunk");
    // JSON chunk longer than the file.
    std::vector<uint8_t> longJson = glb;
    uint32_t huge = 0x7fffffff;
    std::memcpy(&longJson[12], &huge, 4);
    EXPECT_MENTIONS(bytesError(longJson, true), "JSON chunk");
}

TEST(GltfErrors, GlbBytesGivenAsJson) {
    EXPECT_MENTIONS(bytesError(quadScene().glb(), false), "binary GLB");
}

TEST(GltfErrors, FileLargerThanTheLimit) {
    GltfLoadLimits limits;
    limits.maxFileBytes = 100;
    EXPECT_MENTIONS(bytesError(textBytes(quadScene().embedded().dump()), false, limits), "limit");
}

TEST(GltfErrors, MainFileMissingOrLargerThanTheLimit) {
    TempDir dir;
    auto file = dir.write("scene.gltf", textBytes(quadScene().embedded().dump()));
    GltfLoadLimits limits;
    limits.maxFileBytes = 64;
    EXPECT_MENTIONS(errorOf([&] { loadGltfFile(file, limits); }), "more than the limit of 64");
    EXPECT_MENTIONS(errorOf([&] { loadGltfFile(dir.path() / "absent.gltf"); }), "cannot open");
    EXPECT_MENTIONS(errorOf([&] { loadGltfFile(dir.path()); }), "not a regular file");
}

TEST(GltfErrors, TinygltfParseErrorsAreOneLine) {
    GltfBuilder b = quadScene();
    json doc = b.embedded();
    doc["accessors"][0].erase("componentType");
    EXPECT_MENTIONS(jsonError(doc), "componentType");
}

// ---- buffers, views, accessors ----

TEST(GltfErrors, BufferByteLengthMismatch) {
    GltfBuilder b = quadScene();
    json doc = b.embedded();
    doc["buffers"][0]["byteLength"] = b.bin.size() + 8;
    EXPECT_MENTIONS(jsonError(doc), "buffer 0: its data: URI holds");
}

TEST(GltfErrors, AccessorOutOfBoundsOfItsBufferView) {
    GltfBuilder b = quadScene();
    b.doc["accessors"][0]["count"] = 5;  // POSITION: 4 vertices in the view
    EXPECT_MENTIONS(jsonError(b.embedded()), "reach past the end");
    GltfBuilder c = quadScene();
    c.doc["accessors"][0]["byteOffset"] = 40;
    EXPECT_MENTIONS(jsonError(c.embedded()), "reach past the end");
}

TEST(GltfErrors, BufferViewOutOfBoundsOfItsBuffer) {
    GltfBuilder b = quadScene();
    b.doc["bufferViews"][0]["byteLength"] = b.bin.size() + 100;
    EXPECT_MENTIONS(jsonError(b.embedded()), "out of bounds of buffer");
    GltfBuilder c = quadScene();
    c.doc["bufferViews"][0]["byteOffset"] = std::numeric_limits<uint64_t>::max() - 4;
    EXPECT_MENTIONS(jsonError(c.embedded()), "out of bounds of buffer");
}

TEST(GltfErrors, CountTimesStrideIsCheckedIn64Bits) {
    // 2^32 + 1 elements with stride 252: 32-bit math would wrap to a small, "valid" size.
    GltfLoadLimits limits;
    limits.maxTriangles = std::numeric_limits<uint64_t>::max();
    GltfBuilder b = quadScene();
    b.doc["bufferViews"][0]["byteStride"] = 252;
    b.doc["accessors"][0]["count"] = (uint64_t(1) << 32) + 1;
    EXPECT_MENTIONS(jsonError(b.embedded(), {}, limits), "reach past the end");
}

TEST(GltfErrors, AbsurdCountsHitTheLimits) {
    GltfBuilder b = quadScene();
    b.doc["accessors"][0]["count"] = uint64_t(1) << 50;
    EXPECT_MENTIONS(jsonError(b.embedded()), "exceeds the limit");
    // Without a bufferView nothing bounds the count by the file's size.
    GltfBuilder c = quadScene();
    c.doc["accessors"][0].erase("bufferView");
    c.doc["accessors"][0]["count"] = 100'000'000;
    EXPECT_MENTIONS(jsonError(c.embedded()), "implausibly large");
}

TEST(GltfErrors, ManyPrimitivesSharingAnAccessorHitTheDecodeBudget) {
    // Each primitive re-reads the same accessor; the total work is bounded by the triangle limit.
    GltfLoadLimits limits;
    limits.maxTriangles = 1000;  // budget: 16 * 1000 + 2^20 elements
    GltfBuilder b;
    int pos = b.floats(std::vector<float>(3 * 3000, 0.5f), "VEC3");
    int idx = b.indices<uint16_t>({0, 1, 2});
    b.doc["accessors"][pos]["count"] = 3000;
    json prims = json::array();
    for (int i = 0; i < 400; ++i)
        prims.push_back({{"attributes", {{"POSITION", pos}}}, {"indices", idx}});
    b.scene({b.node({{"mesh", b.mesh(prims)}})});
    EXPECT_MENTIONS(jsonError(b.embedded(), {}, limits), "elements in all (the limit)");
}

TEST(GltfErrors, TriangleLimit) {
    GltfLoadLimits limits;
    limits.maxTriangles = 3;
    GltfBuilder b;
    int mesh = b.mesh(json::array({quadPrimitive(b)}));
    b.scene({b.node({{"mesh", mesh}}), b.node({{"mesh", mesh}})});  // 4 triangles in all
    EXPECT_MENTIONS(jsonError(b.embedded(), {}, limits), "more than 3 triangles");
}

TEST(GltfErrors, MissingBufferViewAndBuffer) {
    GltfBuilder b = quadScene();
    b.doc["accessors"][0]["bufferView"] = 42;
    EXPECT_MENTIONS(jsonError(b.embedded()), "bufferView index 42");
    GltfBuilder c = quadScene();
    c.doc["bufferViews"][0]["buffer"] = 3;
    EXPECT_MENTIONS(jsonError(c.embedded()), "buffer index 3");
}

TEST(GltfErrors, InvalidComponentTypeAndType) {
    GltfBuilder b = quadScene();
    b.doc["accessors"][0]["componentType"] = 5124;  // INT: not allowed in glTF 2.0 accessors
    EXPECT_MENTIONS(jsonError(b.embedded()), "componentType 5124");
    GltfBuilder c = quadScene();
    c.doc["accessors"][0]["type"] = "VEC2";
    EXPECT_MENTIONS(jsonError(c.embedded()), "expected 3");
    GltfBuilder d = quadScene();
    int idx = d.doc["meshes"][0]["primitives"][0]["indices"];
    d.doc["accessors"][idx]["componentType"] = kFloat;
    EXPECT_MENTIONS(jsonError(d.embedded()), "index componentType");
}

TEST(GltfErrors, IndexOutOfRangeOfVertexCount) {
    GltfBuilder b;
    json prim = quadPrimitive(b);
    prim["indices"] = b.indices<uint32_t>({0, 1, 2, 0, 2, 4});
    b.scene({b.node({{"mesh", b.mesh(json::array({prim}))}})});
    EXPECT_MENTIONS(jsonError(b.embedded()), "index 4 (entry 5) is out of range of the 4 vertices");
}

TEST(GltfErrors, NonFinitePositions) {
    for (float bad : {NAN, INFINITY}) {
        GltfBuilder b;
        json prim = {
            {"attributes", {{"POSITION", b.floats({0, 0, 0, 1, 0, 0, 0, bad, 0}, "VEC3")}}}};
        b.scene({b.node({{"mesh", b.mesh(json::array({prim}))}})});
        EXPECT_MENTIONS(jsonError(b.embedded()), "NaN or infinite");
    }
}

TEST(GltfErrors, AttributeCountMismatch) {
    GltfBuilder b;
    json prim = quadPrimitive(b);
    prim["attributes"]["NORMAL"] = b.floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
    b.scene({b.node({{"mesh", b.mesh(json::array({prim}))}})});
    EXPECT_MENTIONS(jsonError(b.embedded()), "NORMAL has 3 elements but POSITION has 4");
}

TEST(GltfErrors, SparseIndexOutOfRange) {
    GltfBuilder b = quadScene();
    b.doc["accessors"][0]["sparse"] = {
        {"count", 1},
        {"indices", {{"bufferView", b.view({9, 0, 0, 0})}, {"componentType", kUByte}}},
        {"values", {{"bufferView", b.view(bytesOf(std::vector<float>{1, 1, 1}))}}}};
    EXPECT_MENTIONS(jsonError(b.embedded()), "sparse index 9 is out of range");
}

TEST(GltfErrors, SparseValuesOutOfBounds) {
    GltfBuilder b = quadScene();
    b.doc["accessors"][0]["sparse"] = {
        {"count", 2},
        {"indices", {{"bufferView", b.view({0, 1, 0, 0})}, {"componentType", kUByte}}},
        {"values", {{"bufferView", b.view(bytesOf(std::vector<float>{1, 1, 1}))}}}};
    EXPECT_MENTIONS(jsonError(b.embedded()), "sparse values");
}

TEST(GltfErrors, InvalidPrimitiveMode) {
    GltfBuilder b = quadScene();
    b.doc["meshes"][0]["primitives"][0]["mode"] = 9;
    EXPECT_MENTIONS(jsonError(b.embedded()), "invalid primitive mode 9");
}

// ---- references between objects ----

TEST(GltfErrors, MeshIndexOutOfRange) {
    GltfBuilder b = quadScene();
    b.doc["nodes"][0]["mesh"] = 3;
    EXPECT_MENTIONS(jsonError(b.embedded()), "mesh index 3 is out of range");
}

TEST(GltfErrors, MaterialIndexOutOfRange) {
    GltfBuilder b = quadScene();
    b.doc["meshes"][0]["primitives"][0]["material"] = 2;
    EXPECT_MENTIONS(jsonError(b.embedded()), "material index 2 is out of range");
}

TEST(GltfErrors, NodeIndexOutOfRange) {
    GltfBuilder b = quadScene();
    b.doc["scenes"][0]["nodes"] = {0, 7};
    EXPECT_MENTIONS(jsonError(b.embedded()), "node index 7 is out of range");
    GltfBuilder c = quadScene();
    c.doc["nodes"][0]["children"] = {-2};
    EXPECT_MENTIONS(jsonError(c.embedded()), "node index -2 is out of range");
}

TEST(GltfErrors, DefaultSceneOutOfRange) {
    GltfBuilder b = quadScene();
    b.doc["scene"] = 4;
    EXPECT_MENTIONS(jsonError(b.embedded()), "default scene index 4");
}

TEST(GltfErrors, HierarchyCycle) {
    GltfBuilder b = quadScene();
    b.doc["nodes"][0]["children"] = {1};
    b.node({{"children", {0}}});
    EXPECT_MENTIONS(jsonError(b.embedded()), "cycle");
    GltfBuilder self = quadScene();
    self.doc["nodes"][0]["children"] = {0};
    EXPECT_MENTIONS(jsonError(self.embedded()), "cycle");
}

TEST(GltfErrors, HierarchyTooDeep) {
    GltfBuilder b = quadScene();
    int previous = 0;
    for (int i = 0; i < 300; ++i) {
        int n = b.node(json::object());
        b.doc["nodes"][previous]["children"] = {n};
        previous = n;
    }
    EXPECT_MENTIONS(jsonError(b.embedded()), "deeper than 256");
}

TEST(GltfErrors, MalformedNodeTransform) {
    GltfBuilder b = quadScene();
    b.doc["nodes"][0]["matrix"] = std::vector<double>(15, 1.0);
    EXPECT_MENTIONS(jsonError(b.embedded()), "matrix has 15 numbers");
    // 1e999 parses as infinity.
    std::string text = quadScene({{"translation", {1, 2, 3}}}).embedded().dump();
    size_t at = text.find("[1,2,3]");
    ASSERT_NE(at, std::string::npos);
    text.replace(at, 7, "[1e999,2,3]");
    std::string error = textError(text);
    EXPECT_TRUE(error.find("NaN or infinite") != std::string::npos ||
                error.find("invalid JSON") != std::string::npos)
        << error;
}

TEST(GltfErrors, EmptySceneHasNoTriangles) {
    GltfBuilder b;
    b.scene({b.node(json::object())});
    EXPECT_MENTIONS(jsonError(b.embedded()), "scene has no triangles");
    EXPECT_MENTIONS(textError("{\"asset\": {\"version\": \"2.0\"}}"), "scene has no triangles");
}

}  // namespace
}  // namespace partita
