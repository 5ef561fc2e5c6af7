// Orchestration of a glTF load: preflight checks on the raw bytes, tinygltf parsing with our I/O
// callbacks, then materials, the default scene's node hierarchy, meshes, cameras and lights.
#include "gltf/gltf_loader.h"

#include <climits>
#include <cmath>
#include <cstring>
#include <fstream>
#include <new>
#include <optional>
#include <string_view>

#include "gltf/gltf_cameras.h"
#include "gltf/gltf_common.h"
#include "gltf/gltf_extensions.h"
#include "gltf/gltf_io.h"
#include "gltf/gltf_lights.h"
#include "gltf/gltf_materials.h"
#include "gltf/gltf_meshes.h"
#include "gltf/gltf_nodes.h"
#include "gltf/gltf_preflight.h"
#include "gltf/gltf_textures.h"

namespace partita {

namespace {

using namespace gltf;

// Real glTF JSON nests about 8 levels; `extras` may add some. Far below what would exhaust the
// stack in tinygltf's recursive conversion.
constexpr int kMaxJsonDepth = 128;

/// tinygltf's multi-line messages as one printable line of bounded length.
std::string oneLine(const std::string& text) {
    constexpr size_t kMaxLength = 300;
    std::string out;
    for (char c : text) {
        if (out.size() >= kMaxLength) return out + "...";
        if (c == '\n' || c == '\r') {
            if (!out.empty() && out.back() != ' ') out += "; ";
        } else {
            out += (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) ? '?' : c;
        }
    }
    while (!out.empty() && (out.back() == ' ' || out.back() == ';')) out.pop_back();
    return out;
}

bool looksLikeGlb(const std::vector<uint8_t>& bytes) {
    return bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
}

tinygltf::Model parseModel(const std::vector<uint8_t>& bytes, bool isBinary, TinyGltfIo& io,
                           std::string& warnings) {
    std::string_view json;
    uint32_t glbLength = 0;
    if (isBinary) {
        GlbLayout layout = validateGlb(bytes);
        json = layout.json;
        glbLength = layout.length;
    } else {
        if (looksLikeGlb(bytes)) fail("data is a binary GLB but was given as JSON glTF");
        if (bytes.size() > UINT32_MAX) fail("glTF JSON is larger than 4 GiB");
        json = std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    }
    checkJsonNesting(json, kMaxJsonDepth);
    checkGltfJson(json);

    tinygltf::TinyGLTF loader;
    io.install(loader);
    tinygltf::Model model;
    std::string err;
    // An empty base_dir: tinygltf then asks our callbacks for the (decoded) uri itself.
    bool ok =
        isBinary ? loader.LoadBinaryFromMemory(&model, &err, &warnings, bytes.data(), glbLength, "")
                 : loader.LoadASCIIFromString(&model, &err, &warnings, json.data(),
                                              unsigned(json.size()), "");
    if (!ok) {
        if (!io.firstError().empty() && err.find(io.firstError()) != std::string::npos)
            fail("cannot read a buffer: " + io.firstError());
        fail("glTF parse error: " + oneLine(err));
    }
    return model;
}

void reportParserWarnings(LoadContext& ctx, const std::string& warnings) {
    size_t start = 0;
    while (start < warnings.size()) {
        size_t end = warnings.find('\n', start);
        if (end == std::string::npos) end = warnings.size();
        std::string line = warnings.substr(start, end - start);
        if (!line.empty()) ctx.warn(oneLine(line));
        start = end + 1;
    }
}

/// True when `m` can place geometry: finite and invertible 3x3.
bool isUsableTransform(const Mat4& m) {
    float det = m.determinant3x3();
    return std::isfinite(det) && det != 0.f;
}

/// Decodes each mesh once, however many nodes instance it.
class MeshCache {
  public:
    explicit MeshCache(LoadContext& ctx) : ctx_(ctx), meshes_(ctx.model.meshes.size()) {}
    const std::vector<PrimitiveGeometry>& get(int mesh) {
        checkedAt(ctx_.model.meshes, mesh, "mesh");
        auto& slot = meshes_[size_t(mesh)];
        if (!slot) slot = decodeMesh(ctx_, mesh);
        return *slot;
    }

  private:
    LoadContext& ctx_;
    std::vector<std::optional<std::vector<PrimitiveGeometry>>> meshes_;
};

void addMeshInstance(LoadContext& ctx, MeshCache& meshes, const tinygltf::Node& node, int index,
                     const Mat4& toWorld) {
    const std::vector<PrimitiveGeometry>& primitives = meshes.get(node.mesh);
    if (!isUsableTransform(toWorld)) {
        ctx.warn(fmt::format(
            "node {}: transform has zero scale or is degenerate; skipping its mesh", index));
        return;
    }
    for (const PrimitiveGeometry& geometry : primitives) {
        uint64_t triangles = geometry.indices.size() / 3;
        if (triangles > ctx.limits.maxTriangles - ctx.trianglesEmitted)
            failf("scene has more than {} triangles (the limit)", ctx.limits.maxTriangles);
        ctx.trianglesEmitted += triangles;
        TriangleMesh mesh = instantiate(geometry, toWorld);
        if (!node.name.empty())
            mesh.name = node.name + (primitives.size() > 1 ? "/" + mesh.name : "");
        ctx.scene.meshes.push_back(std::move(mesh));
    }
}

void addNode(LoadContext& ctx, MeshCache& meshes, const NodeInstance& instance) {
    const tinygltf::Node& node = ctx.model.nodes[size_t(instance.node)];
    if (node.mesh != -1) addMeshInstance(ctx, meshes, node, instance.node, instance.toWorld);
    if (node.camera != -1)
        if (auto cam = convertCamera(ctx, node, instance.node, instance.toWorld))
            ctx.scene.cameras.push_back(std::move(*cam));
    if (auto light = convertNodeLight(ctx, node, instance.node, instance.toWorld))
        ctx.scene.lights.push_back(std::move(*light));
}

void warnAboutIgnoredFeatures(LoadContext& ctx) {
    const tinygltf::Model& model = ctx.model;
    if (!model.skins.empty() || !model.animations.empty())
        ctx.warn("skins and animations are ignored; meshes are used in their bind pose");
    for (const tinygltf::Mesh& mesh : model.meshes)
        for (const tinygltf::Primitive& prim : mesh.primitives)
            if (!prim.targets.empty()) {
                ctx.warn("morph targets are ignored; meshes use their base shape");
                return;
            }
}

SceneData loadModel(const tinygltf::Model& model, const std::string& parserWarnings,
                    const TinyGltfIo& io, const GltfLoadLimits& limits) {
    SceneData scene;
    LoadContext ctx{model, limits, scene};
    reportParserWarnings(ctx, parserWarnings);
    warnAboutIgnoredExtensions(ctx);
    warnAboutIgnoredFeatures(ctx);

    // Every material is converted, used or not, so that primitive material indices carry over.
    TextureCache textures(ctx, io);
    for (size_t i = 0; i < model.materials.size(); ++i)
        scene.materials.push_back(convertMaterial(ctx, textures, int(i)));

    MeshCache meshes(ctx);
    for (const NodeInstance& instance : flattenDefaultScene(ctx)) addNode(ctx, meshes, instance);
    if (ctx.trianglesEmitted == 0) fail("scene has no triangles");
    return scene;
}

SceneData loadUnguarded(const std::vector<uint8_t>& bytes, bool isBinary,
                        const ResourceResolver& resolver, const GltfLoadLimits& limits) {
    if (bytes.size() > limits.maxFileBytes)
        failf("glTF file of {} bytes exceeds the limit of {} bytes", bytes.size(),
              limits.maxFileBytes);
    TinyGltfIo io(resolver, limits.maxFileBytes);
    std::string warnings;
    tinygltf::Model model = parseModel(bytes, isBinary, io, warnings);
    return loadModel(model, warnings, io, limits);
}

std::vector<uint8_t> readMainFile(const std::filesystem::path& file, uint64_t maxBytes) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
        failf("cannot open '{}': not a regular file", printableUri(file.string()));
    uint64_t size = std::filesystem::file_size(file, ec);
    if (ec) failf("cannot open '{}': {}", printableUri(file.string()), ec.message());
    if (size > maxBytes)
        failf("'{}' is {} bytes, more than the limit of {}", printableUri(file.string()), size,
              maxBytes);
    std::vector<uint8_t> bytes(size);
    std::ifstream in(file, std::ios::binary);
    if (!in || !in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size)))
        failf("cannot read '{}'", printableUri(file.string()));
    return bytes;
}

}  // namespace

SceneData loadGltfMemory(const std::vector<uint8_t>& bytes, bool isBinary,
                         const ResourceResolver& resolver, const GltfLoadLimits& limits) {
    // tinygltf and nlohmann report some problems by throwing; the contract is SceneLoadError only.
    try {
        return loadUnguarded(bytes, isBinary, resolver, limits);
    } catch (const SceneLoadError&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw SceneLoadError("out of memory while loading glTF");
    } catch (const std::exception& e) {
        throw SceneLoadError(std::string("glTF error: ") + e.what());
    }
}

SceneData loadGltfFile(const std::filesystem::path& file, const GltfLoadLimits& limits) {
    std::vector<uint8_t> bytes = readMainFile(file, limits.maxFileBytes);
    bool isBinary = looksLikeGlb(bytes) || file.extension() == ".glb";
    std::filesystem::path folder = file.parent_path().empty() ? "." : file.parent_path();
    FolderResolver resolver(folder, limits.maxFileBytes);
    return loadGltfMemory(bytes, isBinary, resolver, limits);
}

}  // namespace partita
