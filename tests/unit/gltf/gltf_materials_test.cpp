// glTF materials, textures, images, samplers and extension handling.
#include <gtest/gtest.h>

#include <cmath>

#include "gltf/gltf_images.h"
#include "gltf/gltf_textures.h"
#include "gltf_test_helpers.h"

namespace partita {
namespace {

using namespace gltftest;

#define EXPECT_MENTIONS(error, text) \
    EXPECT_NE((error).find(text), std::string::npos) << "message: " << (error)

bool hasWarning(const SceneData& s, const std::string& text) {
    for (const auto& w : s.warnings)
        if (w.find(text) != std::string::npos) return true;
    return false;
}

/// The quad scene with `material` as material 0 of its primitive.
GltfBuilder withMaterial(const json& material) {
    GltfBuilder b = quadScene();
    b.doc["materials"] = json::array({material});
    b.doc["meshes"][0]["primitives"][0]["material"] = 0;
    return b;
}

/// 2x1 RGBA PNG: left pixel (128, 64, 255, 128), right pixel (0, 255, 32, 255).
std::vector<uint8_t> twoPixelPng() {
    return makePng(2, 1, 4, {128, 64, 255, 128, 0, 255, 32, 255});
}

void addImage(GltfBuilder& b, const std::vector<uint8_t>& png, const json& sampler = nullptr) {
    b.doc["images"] = json::array({{{"uri", dataUri(png, "image/png")}}});
    json texture = {{"source", 0}};
    if (!sampler.is_null()) {
        b.doc["samplers"] = json::array({sampler});
        texture["sampler"] = 0;
    }
    b.doc["textures"] = json::array({texture});
}

// ---- factors and extensions ----

TEST(GltfMaterials, PbrFactorsAndDoubleSided) {
    GltfBuilder b = withMaterial({{"name", "paint"},
                                  {"pbrMetallicRoughness",
                                   {{"baseColorFactor", {0.5, 0.25, 1.0, 0.75}},
                                    {"metallicFactor", 0.0},
                                    {"roughnessFactor", 0.3}}},
                                  {"emissiveFactor", {1.0, 0.5, 0.0}},
                                  {"doubleSided", true}});
    SceneData s = loadJson(b.embedded());
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_EQ(s.meshes[0].material, 0);
    const Material& m = s.materials[0];
    EXPECT_EQ(m.name, "paint");
    EXPECT_FLOAT_EQ(m.baseColor.y, 0.25f);
    EXPECT_FLOAT_EQ(m.baseAlpha, 0.75f);
    EXPECT_FLOAT_EQ(m.metallic, 0.0f);
    EXPECT_FLOAT_EQ(m.roughness, 0.3f);
    EXPECT_FLOAT_EQ(m.emissiveFactor.x, 1.0f);
    EXPECT_TRUE(m.doubleSided);
    EXPECT_FALSE(m.hasVolume);
    EXPECT_FLOAT_EQ(m.ior, 1.5f);
    EXPECT_TRUE(s.warnings.empty());
}

TEST(GltfMaterials, OutOfRangeFactorsAreClampedWithWarning) {
    SceneData s = loadJson(withMaterial({{"pbrMetallicRoughness",
                                          {{"metallicFactor", 3.0}, {"roughnessFactor", -1.0}}}})
                               .embedded());
    EXPECT_FLOAT_EQ(s.materials[0].metallic, 1.0f);
    EXPECT_FLOAT_EQ(s.materials[0].roughness, 0.0f);
    EXPECT_TRUE(hasWarning(s, "metallicFactor"));
}

TEST(GltfMaterials, EmissiveStrength) {
    SceneData s = loadJson(
        withMaterial(
            {{"emissiveFactor", {1.0, 1.0, 0.5}},
             {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 40.0}}}}}})
            .embedded());
    const Material& m = s.materials[0];
    EXPECT_FLOAT_EQ(m.emissiveStrength, 40.0f);
    EXPECT_FLOAT_EQ(m.emissionScale().z, 20.0f);
    EXPECT_TRUE(m.isEmissive());
}

TEST(GltfMaterials, TransmissionIorAndVolume) {
    SceneData s =
        loadJson(withMaterial({{"pbrMetallicRoughness", {{"roughnessFactor", 0.0}}},
                               {"extensions",
                                {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                                 {"KHR_materials_ior", {{"ior", 1.33}}},
                                 {"KHR_materials_volume",
                                  {{"thicknessFactor", 1.0},
                                   {"attenuationColor", {0.5, 0.6, 0.7}},
                                   {"attenuationDistance", 2.0}}}}}})
                     .embedded());
    const Material& m = s.materials[0];
    EXPECT_FLOAT_EQ(m.transmission, 1.0f);
    EXPECT_FLOAT_EQ(m.ior, 1.33f);
    EXPECT_TRUE(m.hasVolume);
    EXPECT_FLOAT_EQ(m.attenuationColor.z, 0.7f);
    EXPECT_FLOAT_EQ(m.attenuationDistance, 2.0f);
}

TEST(GltfMaterials, VolumeWithDefaultsAndInvalidIor) {
    SceneData s = loadJson(withMaterial({{"extensions",
                                          {{"KHR_materials_volume", json::object()},
                                           {"KHR_materials_ior", {{"ior", 0.5}}}}}})
                               .embedded());
    const Material& m = s.materials[0];
    EXPECT_TRUE(m.hasVolume);
    EXPECT_FLOAT_EQ(m.attenuationColor.x, 1.0f);
    EXPECT_TRUE(std::isinf(m.attenuationDistance));
    EXPECT_FLOAT_EQ(m.ior, 1.5f);
    EXPECT_TRUE(hasWarning(s, "ior 0.5"));
}

// ---- textures ----

TEST(GltfTextures, BaseColorIsDecodedFromSrgbAndAlphaStaysLinear) {
    GltfBuilder b =
        withMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
    addImage(b, twoPixelPng());
    SceneData s = loadJson(b.embedded());
    ASSERT_EQ(s.textures.size(), 1u);
    const Texture& t = s.textures[0];
    EXPECT_EQ(t.width, 2);
    EXPECT_EQ(t.height, 1);
    EXPECT_NEAR(t.channel(0, 0, 0), gltf::srgbToLinear(128 / 255.f), 1e-6);
    EXPECT_NEAR(t.channel(0, 0, 0), 0.2158f, 1e-3);
    EXPECT_NEAR(t.channel(0, 0, 2), 1.0f, 1e-6);
    EXPECT_NEAR(t.channel(0, 0, 3), 128 / 255.f, 1e-6);  // alpha not converted
    EXPECT_NEAR(t.channel(1, 0, 1), 1.0f, 1e-6);
    EXPECT_EQ(s.materials[0].baseColorTexture.texture, 0);
}

TEST(GltfTextures, EightBitImagesKeepTheirBytesAndLookUpAsIfConvertedAtLoad) {
    // A 3x2 RGB image with 8 bits per channel is kept as bytes (four per texel, alpha opaque);
    // lookups give, bit for bit, what a float texture of the converted values gives.
    std::vector<uint16_t> bytes = {0,  1,  2,  127, 128, 129, 200, 254, 255,
                                   17, 64, 99, 255, 0,   33,  5,   250, 180};
    GltfBuilder b =
        withMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
    addImage(b, makePng(3, 2, 3, bytes, 8));
    SceneData s = loadJson(b.embedded());
    const Texture& t = s.textures[0];
    EXPECT_TRUE(t.rgba.empty());
    ASSERT_EQ(t.rgba8.size(), 3u * 2u * 4u);
    Texture converted = t;
    converted.rgba8.clear();
    for (size_t p = 0; p < 6; ++p) {
        for (size_t c = 0; c < 3; ++c)
            converted.rgba.push_back(gltf::srgbToLinear(float(bytes[p * 3 + c]) * (1.f / 255.f)));
        converted.rgba.push_back(1.0f);
    }
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x)
            for (int c = 0; c < 4; ++c)
                EXPECT_EQ(t.channel(x, y, c), converted.rgba[size_t((y * 3 + x) * 4 + c)]);
    for (TextureFilter filter : {TextureFilter::Linear, TextureFilter::Nearest}) {
        Texture eight = t;
        eight.filter = converted.filter = filter;
        for (float u = -1.0f; u <= 2.0f; u += 0.037f)
            for (float v = -1.0f; v <= 2.0f; v += 0.041f) {
                Rgba got = eight.lookup({u, v}), want = converted.lookup({u, v});
                ASSERT_EQ(got.rgb, want.rgb) << u << ", " << v;
                ASSERT_EQ(got.a, want.a) << u << ", " << v;
            }
    }
}

TEST(GltfTextures, MetallicRoughnessIsLinear) {
    GltfBuilder b =
        withMaterial({{"pbrMetallicRoughness", {{"metallicRoughnessTexture", {{"index", 0}}}}}});
    addImage(b, twoPixelPng());
    SceneData s = loadJson(b.embedded());
    EXPECT_NEAR(s.textures[0].channel(0, 0, 0), 128 / 255.f, 1e-6);
    EXPECT_EQ(s.materials[0].metallicRoughnessTexture.texture, 0);
}

TEST(GltfTextures, OneTexturePerImageSamplerAndColourSpace) {
    GltfBuilder b = withMaterial(
        {{"pbrMetallicRoughness",
          {{"baseColorTexture", {{"index", 0}}}, {"metallicRoughnessTexture", {{"index", 0}}}}},
         {"emissiveTexture", {{"index", 1}}}});
    addImage(b, twoPixelPng());
    b.doc["textures"].push_back({{"source", 0}});  // a second texture, same image, same sampler
    SceneData s = loadJson(b.embedded());
    // base colour + emissive share the sRGB texture; metallic-roughness gets a linear one.
    EXPECT_EQ(s.textures.size(), 2u);
    EXPECT_EQ(s.materials[0].baseColorTexture.texture, s.materials[0].emissiveTexture.texture);
    EXPECT_NE(s.materials[0].baseColorTexture.texture,
              s.materials[0].metallicRoughnessTexture.texture);
}

TEST(GltfTextures, TexCoordSetAndTextureTransform) {
    GltfBuilder b = withMaterial({{"pbrMetallicRoughness",
                                   {{"baseColorTexture", {{"index", 0}, {"texCoord", 1}}},
                                    {"metallicRoughnessTexture",
                                     {{"index", 0},
                                      {"extensions",
                                       {{"KHR_texture_transform",
                                         {{"offset", {0.5, 0.25}},
                                          {"rotation", 1.5},
                                          {"scale", {2, 3}},
                                          {"texCoord", 1}}}}}}}}},
                                  {"emissiveTexture", {{"index", 0}, {"texCoord", 4}}}});
    addImage(b, twoPixelPng());
    SceneData s = loadJson(b.embedded());
    const Material& m = s.materials[0];
    EXPECT_EQ(m.baseColorTexture.texCoord, 1);
    EXPECT_FALSE(m.baseColorTexture.hasTransform);
    const TextureRef& mr = m.metallicRoughnessTexture;
    EXPECT_TRUE(mr.hasTransform);
    EXPECT_EQ(mr.texCoord, 1);  // the transform's texCoord overrides the slot's
    EXPECT_FLOAT_EQ(mr.offset.x, 0.5f);
    EXPECT_FLOAT_EQ(mr.offset.y, 0.25f);
    EXPECT_FLOAT_EQ(mr.rotation, 1.5f);
    EXPECT_FLOAT_EQ(mr.scale.y, 3.0f);
    EXPECT_EQ(m.emissiveTexture.texCoord, 0);  // TEXCOORD_4 is not loaded: warning, set 0
    EXPECT_TRUE(hasWarning(s, "TEXCOORD_4"));
}

TEST(GltfTextures, TransmissionTextureInsideTheExtension) {
    GltfBuilder b = withMaterial(
        {{"extensions",
          {{"KHR_materials_transmission",
            {{"transmissionFactor", 0.5},
             {"transmissionTexture",
              {{"index", 0},
               {"texCoord", 1},
               {"extensions", {{"KHR_texture_transform", {{"scale", {4, 4}}}}}}}}}}}}});
    addImage(b, twoPixelPng());
    SceneData s = loadJson(b.embedded());
    const TextureRef& t = s.materials[0].transmissionTexture;
    EXPECT_EQ(t.texture, 0);
    EXPECT_EQ(t.texCoord, 1);
    EXPECT_TRUE(t.hasTransform);
    EXPECT_FLOAT_EQ(t.scale.x, 4.0f);
    EXPECT_FLOAT_EQ(s.materials[0].transmission, 0.5f);
}

TEST(GltfTextures, SamplerWrapModesAndNearestFilter) {
    GltfBuilder b =
        withMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
    addImage(b, twoPixelPng(), {{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}});
    SceneData s = loadJson(b.embedded());
    const Texture& t = s.textures[0];
    EXPECT_EQ(t.wrapS, WrapMode::ClampToEdge);
    EXPECT_EQ(t.wrapT, WrapMode::MirroredRepeat);
    EXPECT_EQ(t.filter, TextureFilter::Nearest);

    GltfBuilder d =
        withMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
    addImage(d, twoPixelPng());
    SceneData defaults = loadJson(d.embedded());
    EXPECT_EQ(defaults.textures[0].wrapS, WrapMode::Repeat);
    EXPECT_EQ(defaults.textures[0].filter, TextureFilter::Linear);
}

TEST(GltfTextures, SixteenBitGreyPng) {
    GltfBuilder b =
        withMaterial({{"pbrMetallicRoughness", {{"metallicRoughnessTexture", {{"index", 0}}}}}});
    addImage(b, makePng(2, 2, 1, {0, 65535, 32768, 1000}, 16));
    SceneData s = loadJson(b.embedded());
    const Texture& t = s.textures[0];
    EXPECT_NEAR(t.channel(1, 0, 0), 1.0f, 1e-6);
    EXPECT_NEAR(t.channel(0, 1, 1), 32768 / 65535.f, 1e-6);  // grey replicated to G
    EXPECT_NEAR(t.channel(0, 1, 3), 1.0f, 1e-6);             // opaque alpha
}

TEST(GltfTextures, ExternalImageFromTheSceneFolder) {
    TempDir dir;
    GltfBuilder b =
        withMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
    b.doc["images"] = json::array({{{"uri", "tex/wood%20grain.png"}}});
    b.doc["textures"] = json::array({{{"source", 0}}});
    dir.write("tex/wood grain.png", twoPixelPng());
    dir.write("scene.bin", b.bin);
    SceneData s = loadGltfFile(dir.write("scene.gltf", textBytes(b.external("scene.bin").dump())));
    ASSERT_EQ(s.textures.size(), 1u);
    EXPECT_EQ(s.textures[0].name, "tex/wood%20grain.png");
}

TEST(GltfTextures, GlbImageInABufferView) {
    GltfBuilder b = withMaterial({{"emissiveTexture", {{"index", 0}}}});
    int view = b.view(twoPixelPng());
    b.doc["images"] = json::array({{{"bufferView", view}, {"mimeType", "image/png"}}});
    b.doc["textures"] = json::array({{{"source", 0}}});
    SceneData s = loadGltfMemory(b.glb(), true, MemoryResolver({}));
    ASSERT_EQ(s.textures.size(), 1u);
    EXPECT_EQ(s.materials[0].emissiveTexture.texture, 0);
    EXPECT_NEAR(s.textures[0].channel(1, 0, 1), 1.0f, 1e-6);
}

// ---- texture errors ----

std::string textureError(const std::function<void(GltfBuilder&)>& edit,
                         const GltfLoadLimits& limits = {}) {
    GltfBuilder b =
        withMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
    addImage(b, twoPixelPng());
    edit(b);
    return jsonError(b.embedded(), {}, limits);
}

TEST(GltfTextureErrors, MissingImageFile) {
    std::string e = textureError([](GltfBuilder& b) { b.doc["images"][0]["uri"] = "nope.png"; });
    EXPECT_MENTIONS(e, "image 0 'nope.png': could not be read");
    EXPECT_MENTIONS(e, "not uploaded");
    std::string escape =
        textureError([](GltfBuilder& b) { b.doc["images"][0]["uri"] = "../../etc/x.png"; });
    EXPECT_MENTIONS(escape, "'..'");
}

TEST(GltfTextureErrors, UndecodableImage) {
    std::vector<uint8_t> corrupt = twoPixelPng();
    for (size_t i = 40; i < corrupt.size(); ++i) corrupt[i] = 0x5A;
    EXPECT_MENTIONS(textureError([&](GltfBuilder& b) {
                        b.doc["images"][0]["uri"] = dataUri(corrupt, "image/png");
                    }),
                    "could not be decoded");
    EXPECT_MENTIONS(textureError([](GltfBuilder& b) {
                        b.doc["images"][0]["uri"] = dataUri({'B', 'M', 1, 2, 3, 4}, "image/bmp");
                    }),
                    "not a PNG or JPEG");
}

TEST(GltfTextureErrors, ImageLargerThanTheLimit) {
    GltfLoadLimits limits;
    limits.maxTexturePixels = 1;
    EXPECT_MENTIONS(textureError([](GltfBuilder&) {}, limits), "exceed the limit of 1 pixels");
}

TEST(GltfTextureErrors, AllTexturesTogetherHaveALimit) {
    // Two textures of the same image (sRGB and linear copies) count twice.
    GltfLoadLimits limits;
    limits.maxTotalTexturePixels = 3;
    GltfBuilder b = withMaterial(
        {{"pbrMetallicRoughness",
          {{"baseColorTexture", {{"index", 0}}}, {"metallicRoughnessTexture", {{"index", 0}}}}}});
    addImage(b, twoPixelPng());
    EXPECT_MENTIONS(jsonError(b.embedded(), {}, limits), "textures exceed the limit of 3 pixels");
    limits.maxTotalTexturePixels = 4;
    EXPECT_EQ(loadJson(b.embedded(), {}, limits).textures.size(), 2u);
}

TEST(GltfTextureErrors, InvalidTextureImageAndSamplerIndices) {
    EXPECT_MENTIONS(textureError([](GltfBuilder& b) {
                        b.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] =
                            5;
                    }),
                    "texture index 5 is out of range");
    EXPECT_MENTIONS(textureError([](GltfBuilder& b) { b.doc["textures"][0]["source"] = 3; }),
                    "image index 3 is out of range");
    EXPECT_MENTIONS(textureError([](GltfBuilder& b) { b.doc["textures"][0]["sampler"] = 2; }),
                    "sampler index 2 is out of range");
    EXPECT_MENTIONS(textureError([](GltfBuilder& b) { b.doc["textures"][0].erase("source"); }),
                    "no PNG/JPEG source");
}

TEST(GltfTextureErrors, ImageBufferViewOutOfBounds) {
    GltfBuilder b = withMaterial({{"emissiveTexture", {{"index", 0}}}});
    int view = b.view(twoPixelPng());
    b.doc["bufferViews"][view]["byteLength"] = 100000;
    b.doc["images"] = json::array({{{"bufferView", view}, {"mimeType", "image/png"}}});
    b.doc["textures"] = json::array({{{"source", 0}}});
    std::string e = errorOf([&] { loadGltfMemory(b.glb(), true, MemoryResolver({})); });
    EXPECT_MENTIONS(e, "out of bounds of buffer");
}

TEST(GltfImages, SniffsPngAndJpegSizes) {
    std::vector<uint8_t> png = makePng(3, 5, 3, std::vector<uint16_t>(45, 7));
    gltf::ImageSize p = gltf::sniffImageSize(png.data(), png.size(), "test");
    EXPECT_EQ(p.width, 3u);
    EXPECT_EQ(p.height, 5u);
    // SOI, an APP0 segment of 4 bytes, then SOF0 with height 480, width 640.
    std::vector<uint8_t> jpeg = {0xFF, 0xD8, 0xFF, 0xE0, 0x00, 0x04, 0x00, 0x00, 0xFF,
                                 0xC0, 0x00, 0x11, 0x08, 0x01, 0xE0, 0x02, 0x80, 0x03};
    gltf::ImageSize j = gltf::sniffImageSize(jpeg.data(), jpeg.size(), "test");
    EXPECT_EQ(j.width, 640u);
    EXPECT_EQ(j.height, 480u);
    std::vector<uint8_t> truncated(jpeg.begin(), jpeg.begin() + 12);
    EXPECT_THROW(gltf::sniffImageSize(truncated.data(), truncated.size(), "t"), SceneLoadError);
}

// ---- extensions ----

TEST(GltfExtensions, RequiredExtensionsWeCannotHonourAreNamed) {
    for (const char* name : {"KHR_draco_mesh_compression", "EXT_meshopt_compression",
                             "KHR_texture_basisu", "KHR_materials_clearcoat"}) {
        GltfBuilder b = quadScene();
        b.doc["extensionsUsed"] = {name};
        b.doc["extensionsRequired"] = {name};
        std::string e = jsonError(b.embedded());
        EXPECT_MENTIONS(e, std::string("required extension ") + name + " is not supported");
    }
}

TEST(GltfExtensions, SupportedRequiredExtensionsLoad) {
    GltfBuilder b = quadScene();
    json names = {"KHR_materials_transmission", "KHR_materials_ior",
                  "KHR_materials_volume",       "KHR_materials_emissive_strength",
                  "KHR_texture_transform",      "KHR_lights_punctual",
                  "KHR_mesh_quantization",      "KHR_materials_variants"};
    b.doc["extensionsUsed"] = names;
    b.doc["extensionsRequired"] = names;
    SceneData s = loadJson(b.embedded());
    EXPECT_EQ(s.meshes.size(), 1u);
    EXPECT_TRUE(s.warnings.empty());
}

TEST(GltfExtensions, UsedButUnsupportedIsAWarning) {
    GltfBuilder b = quadScene();
    b.doc["extensionsUsed"] = {"KHR_materials_clearcoat"};
    SceneData s = loadJson(b.embedded());
    EXPECT_TRUE(hasWarning(s, "KHR_materials_clearcoat is used but not supported"));
}

}  // namespace
}  // namespace partita
