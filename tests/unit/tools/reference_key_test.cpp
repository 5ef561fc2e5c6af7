// Tests of the reference cache key (tools/eval/reference_key): it changes when a setting that
// changes the image or any byte of the scene (file or resource) changes, and not otherwise.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "eval/reference_key.h"
#include "params/job_parameters.h"

namespace partita::eval {
namespace {

namespace fs = std::filesystem;

/// A fresh folder per test holding a small .gltf with one buffer and one image, both external.
class ReferenceKeyTest : public ::testing::Test {
  protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               ("partita-reference-key-" + std::to_string(::getpid()) + "-" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        write("scene.gltf", R"({"asset":{"version":"2.0"},
            "buffers":[{"uri":"mesh.bin","byteLength":4},{"uri":"data:application/octet-stream;base64,AAAA"}],
            "images":[{"uri":"wood%20grain.png"},{"uri":"mesh.bin"}]})");
        write("mesh.bin", "abcd");
        write("wood grain.png", "png bytes");
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    void write(const std::string& name, const std::string& bytes) {
        std::ofstream(dir_ / name, std::ios::binary) << bytes;
    }
    std::string key(const RenderSettings& s = {}, const std::string& algorithm = "pt") {
        return referenceKey(sceneFiles(dir_ / "scene.gltf"), algorithm, s);
    }
    fs::path dir_;
};

TEST_F(ReferenceKeyTest, ListsTheSceneAndEachExternalResourceOnce) {
    auto files = sceneFiles(dir_ / "scene.gltf");
    ASSERT_EQ(files.size(), 3u);  // the data: buffer is inside the file; mesh.bin counts once
    EXPECT_EQ(files[0].name, "scene");
    EXPECT_EQ(files[1].name, "mesh.bin");
    EXPECT_EQ(files[1].size, 4u);
    EXPECT_EQ(files[2].name, "wood%20grain.png");  // found under its percent-decoded name
    EXPECT_EQ(files[2].size, 9u);
}

TEST_F(ReferenceKeyTest, IsStableAndIgnoresWhatDoesNotChangeTheImage) {
    std::string base = key();
    EXPECT_EQ(base.size(), 32u);
    EXPECT_EQ(key(), base);
    RenderSettings s;
    s.previewIntervalSeconds = 0;  // neither previews nor (not a setting here) threads count
    EXPECT_EQ(key(s), base);
    write("unrelated.txt", "not referenced by the scene");
    EXPECT_EQ(key(), base);
    fs::copy_file(dir_ / "scene.gltf",
                  dir_ / "renamed.gltf");  // the scene's own name is not hashed
    EXPECT_EQ(referenceKey(sceneFiles(dir_ / "renamed.gltf"), "pt", {}), base);
}

TEST_F(ReferenceKeyTest, ChangesWithEverySettingThatChangesTheImage) {
    std::string base = key();
    EXPECT_NE(key({}, "bdpt"), base);
    auto changed = [&](auto edit) {
        RenderSettings s;
        edit(s);
        return key(s);
    };
    EXPECT_NE(changed([](RenderSettings& s) { s.width = 321; }), base);
    EXPECT_NE(changed([](RenderSettings& s) { s.height = 241; }), base);
    EXPECT_NE(changed([](RenderSettings& s) { s.cameraName = "top"; }), base);
    EXPECT_NE(changed([](RenderSettings& s) { s.budget = 17; }), base);
    EXPECT_NE(changed([](RenderSettings& s) { s.budgetKind = BudgetKind::MutationsPerPixel; }),
              base);
    EXPECT_NE(changed([](RenderSettings& s) { s.seed = 2; }), base);
    EXPECT_NE(changed([](RenderSettings& s) { s.maxDepth = 15; }), base);
    EXPECT_NE(changed([](RenderSettings& s) { s.maxTypeLayers = 1024; }), base);
    // An algorithm's own parameters, each a declared one: any change of value changes the key,
    // and the default written out is the same key as left unset.
    std::string guided = key({}, "guided");
    for (const ParameterSpec& spec : registeredAlgorithm("guided").parameters) {
        RenderSettings s;
        s.parameters.setValue(spec.name, spec.defaultValue);
        EXPECT_EQ(key(s, "guided"), guided) << spec.name;
    }
    auto changedGuided = [&](const std::string& name, auto value) {
        RenderSettings s;
        s.parameters.set(name, value);
        return key(s, "guided");
    };
    EXPECT_NE(changedGuided("k", 11), guided);
    EXPECT_NE(changedGuided("y", 127), guided);
    EXPECT_NE(changedGuided("radius", 10.5), guided);
    EXPECT_NE(changedGuided("epsilon", 0.02), guided);
    EXPECT_NE(changedGuided("prepass", "pt"), guided);
    EXPECT_NE(changedGuided("bootstrap", 5000), guided);
    EXPECT_NE(changedGuided("chains", 64), guided);
}

TEST_F(ReferenceKeyTest, ChangesWithTheEnvironmentAndItsBytes) {
    std::string base = key();
    RenderSettings colour;
    colour.environment.hasColor = true;
    colour.environment.color = {1, 1, 1};
    std::string withColour = key(colour);
    EXPECT_NE(withColour, base);
    colour.environment.color = {1, 1, 0.5f};
    EXPECT_NE(key(colour), withColour);
    write("sky.exr", "sky bytes");
    RenderSettings file;
    file.environment.file = (dir_ / "sky.exr").string();
    std::string withFile = key(file);
    EXPECT_NE(withFile, base);
    file.environment.rotationDegrees = 90;
    EXPECT_NE(key(file), withFile);
    file.environment.rotationDegrees = 0;
    write("sky.exr", "sky bytez");
    EXPECT_NE(key(file), withFile);
}

TEST_F(ReferenceKeyTest, ChangesWithAnyByteOfTheSceneOrItsResources) {
    std::string base = key();
    write("mesh.bin", "abce");
    std::string afterBuffer = key();
    EXPECT_NE(afterBuffer, base);
    write("wood grain.png", "png bytez");
    std::string afterImage = key();
    EXPECT_NE(afterImage, afterBuffer);
    fs::remove(dir_ / "wood grain.png");  // a missing resource is a state of its own
    EXPECT_NE(key(), afterImage);
    write("wood grain.png", "png bytez");
    EXPECT_EQ(key(), afterImage);
    write("scene.gltf", R"({"asset":{"version":"2.0"}})");
    EXPECT_NE(key(), base);
}

TEST_F(ReferenceKeyTest, ReadsTheJsonChunkOfAGlb) {
    std::string json = R"({"asset":{"version":"2.0"},"buffers":[{"uri":"mesh.bin"}]})";
    while (json.size() % 4) json += ' ';
    auto u32 = [](uint32_t v) {
        return std::string{char(v), char(v >> 8), char(v >> 16), char(v >> 24)};
    };
    write("scene.glb", "glTF" + u32(2) + u32(uint32_t(20 + json.size())) +
                           u32(uint32_t(json.size())) + "JSON" + json);
    auto files = sceneFiles(dir_ / "scene.glb");
    ASSERT_EQ(files.size(), 2u);
    EXPECT_EQ(files[1].name, "mesh.bin");
}

TEST_F(ReferenceKeyTest, TheShippedCornellBoxNamesItsBuffer) {
    auto files = sceneFiles(fs::path(PARTITA_SCENES_DIR) / "cornell" / "cornell.gltf");
    ASSERT_EQ(files.size(), 2u);
    EXPECT_EQ(files[1].name, "cornell.bin");
    EXPECT_NE(files[1].hash, "missing");
}

TEST_F(ReferenceKeyTest, AnUnreadableSceneIsAClearError) {
    EXPECT_THROW(sceneFiles(dir_ / "absent.gltf"), std::runtime_error);
}

TEST(HashBytes, IsFnv1a128) {
    // The FNV-1a 128-bit hash of the empty string is its offset basis.
    EXPECT_EQ(hashBytes("", 0), "6c62272e07bb014262b821756295c58d");
    EXPECT_NE(hashBytes("a", 1), hashBytes("b", 1));
}

}  // namespace
}  // namespace partita::eval
