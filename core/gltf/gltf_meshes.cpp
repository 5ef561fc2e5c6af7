#include "gltf/gltf_meshes.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <optional>

#include "gltf/gltf_accessors.h"
#include "gltf/gltf_common.h"

namespace partita::gltf {

namespace {

/// Unit vector along `v`, or nullopt when `v` is zero or not finite. Scaling by the largest
/// component first keeps very small and very large (but finite) vectors from under/overflowing.
std::optional<Vec3f> unitVector(Vec3f v) {
    if (!isFinite(v)) return std::nullopt;
    float m = std::max(std::fabs(v.x), std::max(std::fabs(v.y), std::fabs(v.z)));
    if (!(m > 0) || !std::isfinite(m)) return std::nullopt;
    return normalize(v / m);
}

std::optional<Vec3f> faceNormal(Vec3f a, Vec3f b, Vec3f c) {
    return unitVector(cross(b - a, c - a));
}

/// Accessor element counts are limited by the triangle budget before anything is allocated.
uint64_t maxElements(const LoadContext& ctx) {
    return std::min<uint64_t>(ctx.limits.maxTriangles, uint64_t(1) << 40) * 3 + 2;
}

std::vector<Vec3f> toVec3(const std::vector<float>& v) {
    std::vector<Vec3f> out(v.size() / 3);
    for (size_t i = 0; i < out.size(); ++i) out[i] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
    return out;
}

std::vector<Vec2f> toVec2(const std::vector<float>& v) {
    std::vector<Vec2f> out(v.size() / 2);
    for (size_t i = 0; i < out.size(); ++i) out[i] = {v[2 * i], v[2 * i + 1]};
    return out;
}

bool hasAttribute(const tinygltf::Primitive& prim, const char* name) {
    return prim.attributes.count(name) != 0;
}

/// Reads an optional per-vertex attribute; its count must match the positions'.
std::vector<float> readVertexAttribute(LoadContext& ctx, const tinygltf::Primitive& prim,
                                       const char* name, int type, size_t vertexCount,
                                       const std::string& where) {
    if (!hasAttribute(prim, name)) return {};
    std::vector<float> values = readFloatAccessor(ctx, prim.attributes.at(name), type,
                                                  maxElements(ctx), where + " " + name);
    if (values.size() / size_t(componentsOf(type)) != vertexCount)
        failf("{}: {} has {} elements but POSITION has {}", where, name,
              values.size() / size_t(componentsOf(type)), vertexCount);
    return values;
}

std::vector<uint32_t> vertexReferences(LoadContext& ctx, const tinygltf::Primitive& prim,
                                       size_t vertexCount, const std::string& where) {
    std::vector<uint32_t> refs;
    if (prim.indices == -1) {
        refs.resize(vertexCount);
        std::iota(refs.begin(), refs.end(), 0u);
        return refs;
    }
    refs = readIndexAccessor(ctx, prim.indices, maxElements(ctx), where + " indices");
    for (size_t k = 0; k < refs.size(); ++k)
        if (refs[k] >= vertexCount)
            failf("{}: index {} (entry {}) is out of range of the {} vertices", where, refs[k], k,
                  vertexCount);
    return refs;
}

int primitiveMaterial(const LoadContext& ctx, const tinygltf::Primitive& prim,
                      const std::string& where) {
    if (prim.material == -1) return -1;
    if (prim.material < 0 || size_t(prim.material) >= ctx.model.materials.size())
        failf("{}: material index {} is out of range (the file has {})", where, prim.material,
              ctx.model.materials.size());
    return prim.material;
}

template <typename T>
void keepReferenced(std::vector<T>& values, const std::vector<uint32_t>& newIndex) {
    if (values.empty()) return;
    std::vector<T> kept;
    for (size_t i = 0; i < values.size(); ++i)
        if (newIndex[i] != UINT32_MAX) kept.push_back(values[i]);
    values = std::move(kept);
}

/// Removes vertices no triangle uses, so that every instance's size is bounded by its triangle
/// count (which the triangle limit bounds), however large the file's vertex arrays are.
void dropUnreferencedVertices(PrimitiveGeometry& g) {
    std::vector<bool> used(g.positions.size());
    for (uint32_t v : g.indices) used[v] = true;
    std::vector<uint32_t> newIndex(g.positions.size(), UINT32_MAX);
    uint32_t next = 0;
    for (size_t i = 0; i < used.size(); ++i)
        if (used[i]) newIndex[i] = next++;
    if (next == g.positions.size()) return;  // all used: the common case
    for (uint32_t& v : g.indices) v = newIndex[v];
    keepReferenced(g.positions, newIndex);
    keepReferenced(g.normals, newIndex);
    keepReferenced(g.uvs[0], newIndex);
    keepReferenced(g.uvs[1], newIndex);
}

/// Decodes one primitive; returns false (after a warning) when it is skipped.
bool decodePrimitive(LoadContext& ctx, const tinygltf::Primitive& prim, const std::string& where,
                     PrimitiveGeometry& out) {
    int mode = prim.mode;
    if (mode >= TINYGLTF_MODE_POINTS && mode <= TINYGLTF_MODE_LINE_STRIP) {
        ctx.warn(where + ": points and lines are not rendered; skipping it");
        return false;
    }
    if (mode < TINYGLTF_MODE_TRIANGLES || mode > TINYGLTF_MODE_TRIANGLE_FAN)
        failf("{}: invalid primitive mode {}", where, mode);
    if (!hasAttribute(prim, "POSITION")) {
        ctx.warn(where + ": no POSITION attribute; skipping it");
        return false;
    }
    out.material = primitiveMaterial(ctx, prim, where);
    out.positions =
        toVec3(readFloatAccessor(ctx, prim.attributes.at("POSITION"), TINYGLTF_TYPE_VEC3,
                                 maxElements(ctx), where + " POSITION"));
    for (Vec3f p : out.positions)
        if (!isFinite(p)) failf("{}: POSITION holds a NaN or infinite value", where);
    size_t n = out.positions.size();
    out.normals = toVec3(readVertexAttribute(ctx, prim, "NORMAL", TINYGLTF_TYPE_VEC3, n, where));
    out.uvs[0] = toVec2(readVertexAttribute(ctx, prim, "TEXCOORD_0", TINYGLTF_TYPE_VEC2, n, where));
    out.uvs[1] = toVec2(readVertexAttribute(ctx, prim, "TEXCOORD_1", TINYGLTF_TYPE_VEC2, n, where));

    std::vector<uint32_t> refs = vertexReferences(ctx, prim, n, where);
    if (mode == TINYGLTF_MODE_TRIANGLES && refs.size() % 3 != 0)
        ctx.warn(where + ": triangle list length is not a multiple of 3; ignoring the rest");
    out.indices = assembleTriangles(mode, refs);
    if (out.indices.empty()) {
        ctx.warn(where + ": has no non-degenerate triangles; skipping it");
        return false;
    }
    dropUnreferencedVertices(out);
    return true;
}

/// For vertices whose normal is unusable: the flat normal of the first triangle that uses them.
void repairNormals(TriangleMesh& mesh) {
    std::vector<bool> bad(mesh.normals.size());
    bool any = false;
    for (size_t i = 0; i < mesh.normals.size(); ++i) {
        std::optional<Vec3f> n = unitVector(mesh.normals[i]);
        bad[i] = !n;
        any |= bad[i];
        mesh.normals[i] = n.value_or(Vec3f(0.f));
    }
    if (!any) return;
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const uint32_t* v = &mesh.indices[t];
        std::optional<Vec3f> n =
            faceNormal(mesh.positions[v[0]], mesh.positions[v[1]], mesh.positions[v[2]]);
        if (!n) continue;
        for (int k = 0; k < 3; ++k) {
            if (!bad[v[k]]) continue;
            mesh.normals[v[k]] = *n;
            bad[v[k]] = false;
        }
    }
    for (size_t i = 0; i < mesh.normals.size(); ++i)
        if (bad[i]) mesh.normals[i] = Vec3f(0, 0, 1);  // unused or only in degenerate triangles
}

/// Every triangle gets its own three vertices carrying the face's flat normal.
void unweldWithFlatNormals(TriangleMesh& mesh) {
    TriangleMesh flat;
    flat.name = std::move(mesh.name);
    flat.material = mesh.material;
    size_t count = mesh.indices.size();
    flat.positions.reserve(count);
    flat.normals.reserve(count);
    for (int s = 0; s < 2; ++s)
        if (!mesh.uvs[s].empty()) flat.uvs[s].reserve(count);
    for (size_t t = 0; t + 2 < count; t += 3) {
        const uint32_t* v = &mesh.indices[t];
        // A degenerate triangle is never hit, so its normal does not matter.
        Vec3f n = faceNormal(mesh.positions[v[0]], mesh.positions[v[1]], mesh.positions[v[2]])
                      .value_or(Vec3f(0, 0, 1));
        for (int k = 0; k < 3; ++k) {
            flat.indices.push_back(uint32_t(flat.positions.size()));
            flat.positions.push_back(mesh.positions[v[k]]);
            flat.normals.push_back(n);
            for (int s = 0; s < 2; ++s)
                if (!mesh.uvs[s].empty()) flat.uvs[s].push_back(mesh.uvs[s][v[k]]);
        }
    }
    mesh = std::move(flat);
}

}  // namespace

std::vector<uint32_t> assembleTriangles(int mode, const std::vector<uint32_t>& v) {
    std::vector<uint32_t> out;
    auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
        if (a == b || b == c || a == c) return;  // zero area; strips use these to restart
        out.insert(out.end(), {a, b, c});
    };
    size_t n = v.size();
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        out.reserve(n - n % 3);
        for (size_t i = 0; i + 2 < n; i += 3) emit(v[i], v[i + 1], v[i + 2]);
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        // glTF 2.0, 3.7.2.1: triangle i is (v_i, v_{i+(1+i%2)}, v_{i+(2-i%2)}).
        for (size_t i = 0; i + 2 < n; ++i) emit(v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]);
    } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
        // Triangle i is (v_{i+1}, v_{i+2}, v_0).
        for (size_t i = 0; i + 2 < n; ++i) emit(v[i + 1], v[i + 2], v[0]);
    }
    return out;
}

std::vector<PrimitiveGeometry> decodeMesh(LoadContext& ctx, int meshIndex) {
    const tinygltf::Mesh& mesh = checkedAt(ctx.model.meshes, meshIndex, "mesh");
    std::string meshName = mesh.name.empty() ? "mesh" + std::to_string(meshIndex) : mesh.name;
    std::vector<PrimitiveGeometry> out;
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
        std::string where = fmt::format("mesh {} primitive {}", meshIndex, p);
        PrimitiveGeometry geometry;
        geometry.name = mesh.primitives.size() > 1 ? fmt::format("{}/{}", meshName, p) : meshName;
        if (decodePrimitive(ctx, mesh.primitives[p], where, geometry))
            out.push_back(std::move(geometry));
    }
    return out;
}

TriangleMesh instantiate(const PrimitiveGeometry& geometry, const Mat4& toWorld) {
    TriangleMesh mesh;
    mesh.name = geometry.name;
    mesh.material = geometry.material;
    mesh.uvs = geometry.uvs;
    mesh.indices = geometry.indices;
    mesh.positions.reserve(geometry.positions.size());
    for (Vec3f p : geometry.positions) {
        Vec3f w = toWorld.transformPoint(p);
        if (!isFinite(w)) failf("{}: world-space positions overflow", geometry.name);
        mesh.positions.push_back(w);
    }
    if (toWorld.determinant3x3() < 0)
        for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
            std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
    if (geometry.normals.empty()) {
        unweldWithFlatNormals(mesh);
        return mesh;
    }
    mesh.normals.reserve(geometry.normals.size());
    for (Vec3f n : geometry.normals) mesh.normals.push_back(toWorld.transformNormal(n));
    repairNormals(mesh);  // normalises, and replaces zero / NaN normals
    return mesh;
}

}  // namespace partita::gltf
