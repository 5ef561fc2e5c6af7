// glTF cameras, camera selection and the default camera, and KHR_lights_punctual.
#include <gtest/gtest.h>

#include <cmath>

#include "gltf/camera_select.h"
#include "gltf_test_helpers.h"

namespace partita {
namespace {

using namespace gltftest;

#define EXPECT_MENTIONS(error, text) \
    EXPECT_NE((error).find(text), std::string::npos) << "message: " << (error)

void expectNear(Vec3f a, Vec3f b, float eps = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, eps);
    EXPECT_NEAR(a.y, b.y, eps);
    EXPECT_NEAR(a.z, b.z, eps);
}

Vec3f column(const Mat4& m, int c) { return {m.m[c][0], m.m[c][1], m.m[c][2]}; }

bool hasWarning(const SceneData& s, const std::string& text) {
    for (const auto& w : s.warnings)
        if (w.find(text) != std::string::npos) return true;
    return false;
}

/// The quad scene plus `cameras`, and a node per extra entry of `nodes` (added as roots).
GltfBuilder withCameras(const json& cameras, const std::vector<json>& nodes) {
    GltfBuilder b = quadScene();
    b.doc["cameras"] = cameras;
    std::vector<int> roots = {0};
    for (const json& n : nodes) roots.push_back(b.node(n));
    b.scene(roots);
    return b;
}

const json kPerspective = {{"type", "perspective"},
                           {"name", "main"},
                           {"perspective", {{"yfov", 0.6}, {"aspectRatio", 1.5}, {"znear", 0.05}}}};

// ---- cameras ----

TEST(GltfCameras, PerspectivePlacedByItsNode) {
    // Rotated 90 degrees about +Y: the view direction (-Z) becomes -X.
    float h = std::sqrt(0.5f);
    SceneData s = loadJson(
        withCameras(json::array({kPerspective}),
                    {{{"camera", 0}, {"translation", {5, 1, 0}}, {"rotation", {0, h, 0, h}}}})
            .embedded());
    ASSERT_EQ(s.cameras.size(), 1u);
    const CameraDesc& c = s.cameras[0];
    EXPECT_EQ(c.type, CameraDesc::Type::Perspective);
    EXPECT_EQ(c.name, "main");
    EXPECT_FLOAT_EQ(c.yfov, 0.6f);
    EXPECT_FLOAT_EQ(c.aspectRatio, 1.5f);
    EXPECT_FLOAT_EQ(c.znear, 0.05f);
    expectNear(c.cameraToWorld.transformPoint({0, 0, 0}), {5, 1, 0});
    expectNear(c.cameraToWorld.transformVector({0, 0, -1}), {-1, 0, 0});
    expectNear(c.cameraToWorld.transformVector({0, 1, 0}), {0, 1, 0});
}

TEST(GltfCameras, Orthographic) {
    json ortho = {{"type", "orthographic"},
                  {"orthographic", {{"xmag", 2.0}, {"ymag", 1.5}, {"znear", 0.0}, {"zfar", 10.0}}}};
    SceneData s =
        loadJson(withCameras(json::array({ortho}), {{{"camera", 0}, {"name", "top"}}}).embedded());
    ASSERT_EQ(s.cameras.size(), 1u);
    EXPECT_EQ(s.cameras[0].type, CameraDesc::Type::Orthographic);
    EXPECT_EQ(s.cameras[0].name, "top");  // unnamed camera: the node's name
    EXPECT_FLOAT_EQ(s.cameras[0].xmag, 2.0f);
    EXPECT_FLOAT_EQ(s.cameras[0].ymag, 1.5f);
}

TEST(GltfCameras, ScaleIsRemovedFromTheCameraTransform) {
    // A parent with non-uniform scale and a child camera: the result must be a rigid transform
    // that still looks the same way.
    GltfBuilder b = withCameras(json::array({kPerspective}), {});
    int cam = b.node({{"camera", 0}, {"translation", {0, 0, 4}}});
    int parent = b.node({{"children", {cam}}, {"scale", {2, 3, 0.5}}});
    b.scene({0, parent});
    SceneData s = loadJson(b.embedded());
    ASSERT_EQ(s.cameras.size(), 1u);
    const Mat4& m = s.cameras[0].cameraToWorld;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(length(column(m, c)), 1.0f, 1e-5);
    EXPECT_NEAR(dot(column(m, 0), column(m, 1)), 0.0f, 1e-6);
    EXPECT_NEAR(m.determinant3x3(), 1.0f, 1e-5);
    expectNear(m.transformPoint({0, 0, 0}), {0, 0, 2});
    expectNear(m.transformVector({0, 0, -1}), {0, 0, -1});
    EXPECT_TRUE(hasWarning(s, "scale"));
}

TEST(GltfCameras, InvalidCamerasAreErrors) {
    json badFov = kPerspective;
    badFov["perspective"]["yfov"] = 0.0;
    EXPECT_MENTIONS(jsonError(withCameras(json::array({badFov}), {{{"camera", 0}}}).embedded()),
                    "yfov");
    json badOrtho = {
        {"type", "orthographic"},
        {"orthographic", {{"xmag", 0.0}, {"ymag", 1.0}, {"znear", 0.0}, {"zfar", 1.0}}}};
    EXPECT_MENTIONS(jsonError(withCameras(json::array({badOrtho}), {{{"camera", 0}}}).embedded()),
                    "xmag");
    EXPECT_MENTIONS(
        jsonError(withCameras(json::array({kPerspective}), {{{"camera", 4}}}).embedded()),
        "camera index 4 is out of range");
}

TEST(GltfCameras, SelectByName) {
    json second = kPerspective;
    second["name"] = "close-up";
    SceneData s = loadJson(
        withCameras(json::array({kPerspective, second}), {{{"camera", 0}}, {{"camera", 1}}})
            .embedded());
    EXPECT_EQ(selectCamera(s, "close-up"), 1);
    EXPECT_EQ(selectCamera(s, "main"), 0);
    EXPECT_EQ(selectCamera(s, ""), 0);
    std::string e = errorOf([&] { selectCamera(s, "wide"); });
    EXPECT_MENTIONS(e, "unknown camera 'wide'");
    EXPECT_MENTIONS(e, "'main', 'close-up'");

    SceneData none = loadJson(quadScene().embedded());
    EXPECT_EQ(selectCamera(none, ""), -1);
    EXPECT_MENTIONS(errorOf([&] { selectCamera(none, "main"); }), "no cameras");
}

TEST(GltfCameras, DefaultCameraFramesTheScene) {
    SceneData s = loadJson(quadScene({{"translation", {10, 20, 30}}}).embedded());
    CameraDesc c = defaultCamera(s);
    EXPECT_EQ(c.type, CameraDesc::Type::Perspective);
    Vec3f eye = c.cameraToWorld.transformPoint({0, 0, 0});
    expectNear(c.cameraToWorld.transformVector({0, 0, -1}), {0, 0, -1});
    EXPECT_NEAR(eye.x, 10.5f, 1e-4);
    EXPECT_NEAR(eye.y, 20.5f, 1e-4);
    EXPECT_GT(eye.z, 30.0f);
    // Every corner of the quad lies inside the vertical and horizontal (square) field of view.
    float tanHalf = std::tan(0.5f * c.yfov);
    for (Vec3f p : s.meshes[0].positions) {
        Vec3f d = p - eye;
        EXPECT_LT(std::fabs(d.y / -d.z), tanHalf);
        EXPECT_LT(std::fabs(d.x / -d.z), tanHalf);
        EXPECT_GT(-d.z, c.znear);
    }
}

// ---- lights ----

GltfBuilder withLights(const json& lights, const std::vector<json>& nodes) {
    GltfBuilder b = withCameras(json::array(), nodes);
    b.doc.erase("cameras");
    b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    b.doc["extensions"] = {{"KHR_lights_punctual", {{"lights", lights}}}};
    return b;
}

json lightRef(int index) { return {{"KHR_lights_punctual", {{"light", index}}}}; }

TEST(GltfLights, PointSpotAndDirectionalInWorldSpace) {
    float h = std::sqrt(0.5f);
    json lights = json::array(
        {{{"type", "point"}, {"name", "bulb"}, {"color", {1.0, 0.5, 0.25}}, {"intensity", 20.0}},
         {{"type", "spot"},
          {"intensity", 5.0},
          {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.4}}}},
         {{"type", "directional"}, {"intensity", 3.0}}});
    SceneData s = loadJson(
        withLights(
            lights,
            {{{"translation", {1, 2, 3}}, {"extensions", lightRef(0)}},
             // Rotated -90 degrees about X: -Z turns into -Y (pointing down).
             {{"translation", {0, 5, 0}}, {"rotation", {-h, 0, 0, h}}, {"extensions", lightRef(1)}},
             {{"rotation", {0, h, 0, h}}, {"extensions", lightRef(2)}}})
            .embedded());
    ASSERT_EQ(s.lights.size(), 3u);
    const PunctualLightDesc& point = s.lights[0];
    EXPECT_EQ(point.type, PunctualLightDesc::Type::Point);
    EXPECT_EQ(point.name, "bulb");
    expectNear(point.position, {1, 2, 3});
    expectNear(point.color, {1.0f, 0.5f, 0.25f});
    EXPECT_FLOAT_EQ(point.intensity, 20.0f);

    const PunctualLightDesc& spot = s.lights[1];
    EXPECT_EQ(spot.type, PunctualLightDesc::Type::Spot);
    expectNear(spot.position, {0, 5, 0});
    expectNear(spot.direction, {0, -1, 0});
    EXPECT_FLOAT_EQ(spot.innerConeAngle, 0.2f);
    EXPECT_FLOAT_EQ(spot.outerConeAngle, 0.4f);

    const PunctualLightDesc& sun = s.lights[2];
    EXPECT_EQ(sun.type, PunctualLightDesc::Type::Directional);
    expectNear(sun.direction, {-1, 0, 0});
    EXPECT_TRUE(s.warnings.empty());
}

TEST(GltfLights, InvalidLightReferences) {
    json lights = json::array({{{"type", "point"}}});
    EXPECT_MENTIONS(jsonError(withLights(lights, {{{"extensions", lightRef(3)}}}).embedded()),
                    "light index 3 is out of range");
    json noIndex = {{"KHR_lights_punctual", {{"lite", 0}}}};
    EXPECT_MENTIONS(jsonError(withLights(lights, {{{"extensions", noIndex}}}).embedded()),
                    "no valid \"light\" index");
}

TEST(GltfLights, UnknownTypeAndBadConeAreWarnings) {
    json lights = json::array(
        {{{"type", "area"}},
         {{"type", "spot"}, {"spot", {{"innerConeAngle", 1.0}, {"outerConeAngle", 3.0}}}}});
    SceneData s =
        loadJson(withLights(lights, {{{"extensions", lightRef(0)}}, {{"extensions", lightRef(1)}}})
                     .embedded());
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_TRUE(hasWarning(s, "unknown type 'area'"));
    EXPECT_TRUE(hasWarning(s, "cone angles"));
    EXPECT_LE(s.lights[0].outerConeAngle, kPi / 2);
    EXPECT_LT(s.lights[0].innerConeAngle, s.lights[0].outerConeAngle);
}

}  // namespace
}  // namespace partita
