// Resource resolvers and the uri policy: a glTF may only read files inside its own folder (or the
// files uploaded with it).
#include <gtest/gtest.h>
#include <unistd.h>

#include "gltf_test_helpers.h"

namespace partita {
namespace {

using namespace gltftest;

TEST(ResolverUriCheck, AcceptsPlainRelativePaths) {
    EXPECT_EQ(checkRelativeUri("scene.bin"), "");
    EXPECT_EQ(checkRelativeUri("textures/wood.png"), "");
    EXPECT_EQ(checkRelativeUri("./a.bin"), "");
    EXPECT_EQ(checkRelativeUri("a..b.bin"), "");  // dots inside a name are fine
}

TEST(ResolverUriCheck, RefusesEscapesSchemesAndOddBytes) {
    EXPECT_NE(checkRelativeUri(""), "");
    EXPECT_NE(checkRelativeUri("../x.bin").find("'..'"), std::string::npos);
    EXPECT_NE(checkRelativeUri("a/../../x.bin").find("'..'"), std::string::npos);
    EXPECT_NE(checkRelativeUri("a/..").find("'..'"), std::string::npos);
    EXPECT_NE(checkRelativeUri("/etc/passwd").find("absolute"), std::string::npos);
    EXPECT_NE(checkRelativeUri("file:///etc/passwd").find("scheme"), std::string::npos);
    EXPECT_NE(checkRelativeUri("http://example.com/x.bin").find("scheme"), std::string::npos);
    EXPECT_NE(checkRelativeUri("C:/x.bin").find("drive"), std::string::npos);
    EXPECT_NE(checkRelativeUri("a\\..\\x.bin").find("backslash"), std::string::npos);
    EXPECT_NE(checkRelativeUri(std::string("a\0b", 3)).find("NUL"), std::string::npos);
    EXPECT_NE(checkRelativeUri("data:image/ktx2;base64,AAAA").find("data:"), std::string::npos);
}

TEST(MemoryResolver, ServesUploadsAndRefusesTheRest) {
    MemoryResolver resolver({{"a.bin", {1, 2, 3}}, {"dir/b.bin", {4}}});
    std::string error;
    auto a = resolver.read("a.bin", error);
    ASSERT_TRUE(a.has_value());
    EXPECT_EQ(*a, (std::vector<uint8_t>{1, 2, 3}));
    EXPECT_TRUE(resolver.read("dir//b.bin", error).has_value());
    EXPECT_FALSE(resolver.read("missing.bin", error).has_value());
    EXPECT_NE(error.find("not uploaded"), std::string::npos);
    EXPECT_FALSE(resolver.read("dir/../a.bin", error).has_value());
    EXPECT_NE(error.find("refused"), std::string::npos);
}

class FolderResolverTest : public ::testing::Test {
  protected:
    void SetUp() override {
        scene = std::make_unique<TempDir>();
        outside = std::make_unique<TempDir>();
        outside->write("secret.bin", {9, 9, 9, 9});
        scene->write("inside.bin", {1, 2, 3, 4});
        scene->write("sub/deeper.bin", {5});
    }
    std::unique_ptr<TempDir> scene, outside;
};

TEST_F(FolderResolverTest, ReadsFilesInsideTheFolder) {
    FolderResolver resolver(scene->path());
    std::string error;
    EXPECT_TRUE(resolver.read("inside.bin", error).has_value()) << error;
    EXPECT_TRUE(resolver.read("sub/deeper.bin", error).has_value()) << error;
    EXPECT_FALSE(resolver.read("nope.bin", error).has_value());
    EXPECT_NE(error.find("not found"), std::string::npos);
    EXPECT_FALSE(resolver.read("sub", error).has_value());
    EXPECT_NE(error.find("not a regular file"), std::string::npos);
}

TEST_F(FolderResolverTest, RefusesPathsOutOfTheFolder) {
    FolderResolver resolver(scene->path() / "sub");
    std::string error;
    EXPECT_FALSE(resolver.read("../inside.bin", error).has_value());
    EXPECT_NE(error.find("'..'"), std::string::npos);
    EXPECT_FALSE(resolver.read((outside->path() / "secret.bin").string(), error).has_value());
    EXPECT_NE(error.find("absolute"), std::string::npos);
    EXPECT_FALSE(resolver.read("file://" + (outside->path() / "secret.bin").string(), error));
}

TEST_F(FolderResolverTest, RefusesSymlinksThatLeaveTheFolder) {
    std::filesystem::create_symlink(outside->path() / "secret.bin", scene->path() / "link.bin");
    std::filesystem::create_directory_symlink(outside->path(), scene->path() / "linkdir");
    std::filesystem::create_symlink(scene->path() / "inside.bin", scene->path() / "ok.bin");
    FolderResolver resolver(scene->path());
    std::string error;
    EXPECT_FALSE(resolver.read("link.bin", error).has_value());
    EXPECT_NE(error.find("outside the scene folder"), std::string::npos);
    EXPECT_FALSE(resolver.read("linkdir/secret.bin", error).has_value());
    EXPECT_NE(error.find("outside the scene folder"), std::string::npos);
    EXPECT_TRUE(resolver.read("ok.bin", error).has_value()) << error;
}

TEST_F(FolderResolverTest, EnforcesTheSizeLimit) {
    FolderResolver resolver(scene->path(), 3);
    std::string error;
    EXPECT_FALSE(resolver.read("inside.bin", error).has_value());
    EXPECT_NE(error.find("limit"), std::string::npos);
}

// ---- the same policy end to end, through the loader ----

std::string loadFromFolderWithUri(const TempDir& dir, const std::string& uri) {
    GltfBuilder b = quadScene();
    auto file = dir.write("scene.gltf", textBytes(b.external(uri).dump()));
    return errorOf([&] { loadGltfFile(file); });
}

TEST_F(FolderResolverTest, LoaderRefusesTraversalUris) {
    // Plant a real buffer outside the scene folder so that only the policy can stop the read.
    GltfBuilder b = quadScene();
    outside->write("x.bin", b.bin);
    std::string rel = "../" + outside->path().filename().string() + "/x.bin";

    EXPECT_NE(loadFromFolderWithUri(*scene, rel).find("'..'"), std::string::npos);
    EXPECT_NE(
        loadFromFolderWithUri(*scene, "%2e%2e/" + outside->path().filename().string() + "/x.bin")
            .find("'..'"),
        std::string::npos);
    EXPECT_NE(loadFromFolderWithUri(*scene, (outside->path() / "x.bin").string()).find("absolute"),
              std::string::npos);
    EXPECT_NE(loadFromFolderWithUri(*scene, "file:///etc/passwd").find("scheme"),
              std::string::npos);
    std::filesystem::create_symlink(outside->path() / "x.bin", scene->path() / "x.bin");
    EXPECT_NE(loadFromFolderWithUri(*scene, "x.bin").find("outside the scene folder"),
              std::string::npos);
}

TEST(GltfResolverLoader, MissingBufferIsAClearError) {
    std::string error = jsonError(quadScene().external("missing.bin"));
    EXPECT_NE(error.find("missing.bin"), std::string::npos) << error;
    EXPECT_NE(error.find("not uploaded"), std::string::npos) << error;
}

TEST(GltfResolverLoader, MemoryResolverRefusesTraversal) {
    GltfBuilder b = quadScene();
    std::string error = jsonError(b.external("../quad.bin"), {{"quad.bin", b.bin}});
    EXPECT_NE(error.find("'..'"), std::string::npos) << error;
}

}  // namespace
}  // namespace partita
