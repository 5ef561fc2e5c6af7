#include "path/path.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "bsdfs/bound_bsdf.h"
#include "camera.h"
#include "light_emission.h"
#include "path/dirac_vertex.h"
#include "path/random_walk.h"
#include "path/transmittance.h"
#include "render_scene.h"

namespace partita {

namespace {

Vec3f unitTo(const PathVertex& from, const PathVertex& to) { return normalize(to.p - from.p); }

const Light& lightOf(const RenderScene& scene, const PathVertex& v) {
    return scene.lights()[size_t(v.light)];
}

/// What the light vertex x_M sends towards x_{M-1}, times the light end of the last edge
/// (|cos_g(x_M)| / d^2, or 1 for a directional light).
Rgb lightEnd(const RenderScene& scene, const PathVertex& light, const PathVertex& before) {
    Rgb emitted = emittedTowards(scene, light, before.p);
    if (isInfiniteLight(lightOf(scene, light))) return emitted;
    Vec3f d = before.p - light.p;
    float dist2 = lengthSquared(d);
    return emitted * (geometricCos(light, d / std::sqrt(dist2)) / dist2);
}

}  // namespace

Rgb pathContribution(const RenderScene& scene, const Camera& camera,
                     std::span<const PathVertex> path, DiracVertices dirac) {
    size_t n = path.size();
    if (n < 2 || !camera.isConnectable()) return Rgb(0.0f);
    const PathVertex& x0 = path[0];
    const PathVertex& x1 = path[1];
    Vec3f w01 = unitTo(x0, x1);
    // We and the camera end of the first edge: the cosine to the view direction.
    Rgb f(camera.importance(w01) * dot(w01, camera.forward()));
    if (n > 2) f *= geometricCos(x1, w01) / lengthSquared(x1.p - x0.p);  // (else lightEnd's)
    for (size_t i = 1; i + 1 < n; ++i) {
        const PathVertex& x = path[i];
        if (!x.isSurface() || (x.delta && dirac == DiracVertices::Zero)) return Rgb(0.0f);
        Vec3f toEye = unitTo(x, path[i - 1]), toLight = unitTo(x, path[i + 1]);
        Rgb fs =
            x.delta ? diracBranch(x, toEye, toLight).f : BoundBsdf(x.bsdf, toEye).eval(toLight);
        f *= fs * absDot(toLight, x.hit.ns);
        if (i + 2 < n) {  // the edge to the next scattering vertex: its cos_g and 1 / d^2
            const PathVertex& next = path[i + 1];
            f *= geometricCos(next, toLight) / lengthSquared(next.p - x.p);
        }
    }
    for (size_t i = 0; i + 1 < n; ++i) f *= edgeTransmittance(scene, path[i], path[i + 1]);
    return f * lightEnd(scene, path[n - 1], path[n - 2]);
}

float pathLuminance(const RenderScene& scene, const Camera& camera,
                    std::span<const PathVertex> path, DiracVertices dirac) {
    return luminance(pathContribution(scene, camera, path, dirac));
}

std::vector<VertexDensities> recomputeDensities(const RenderScene& scene, const Camera& camera,
                                                std::span<const PathVertex> path,
                                                DiracVertices dirac) {
    size_t n = path.size();
    std::vector<VertexDensities> x(n);
    if (n < 2) return x;
    for (size_t i = 0; i < n; ++i) x[i].connectable = path[i].isConnectable();
    x[0].fromEye = 1;
    const PathVertex& x0 = path[0];
    const PathVertex& x1 = path[1];
    Vec3f w01 = unitTo(x0, x1);
    x[1].fromEye = camera.isOrthographic() ? camera.directionPdf(w01) * geometricCos(x1, w01)
                                           : solidAngleToArea(camera.directionPdf(w01), x0, x1);
    // BSDF-sampled densities, one way then the other; a Dirac vertex generates "0" (mis.h) or
    // its branch's probability (dirac_vertex.h; `from` < `to`: sampled from the camera side).
    auto bsdfDensity = [&](size_t at, size_t from, size_t to) {
        const PathVertex& v = path[at];
        if (!v.isSurface() || (v.delta && dirac == DiracVertices::Zero)) return 0.0f;
        Vec3f wFrom = unitTo(v, path[from]), wTo = unitTo(v, path[to]);
        float pdf = 0;
        if (!v.delta) {
            pdf = BoundBsdf(v.bsdf, wFrom).pdf(wTo);
        } else if (from < to) {
            pdf = diracBranch(v, wFrom, wTo).probabilityEye;
        } else {
            DiracBranch b = diracBranch(v, wTo, wFrom);
            pdf = b.probabilityLight * b.jacobian;
        }
        return solidAngleToArea(pdf, v, path[to]);
    };
    for (size_t i = 2; i < n; ++i) x[i].fromEye = bsdfDensity(i - 1, i - 2, i);
    const PathVertex& light = path[n - 1];
    x[n - 1].fromLight = lightVertexDensity(scene, light.light, unitTo(path[n - 2], light));
    x[n - 2].fromLight =
        densityTowards(lightOf(scene, light), light.p, light.ng, path[n - 2].p, path[n - 2].ng);
    for (size_t i = n - 2; i-- > 0;) x[i].fromLight = bsdfDensity(i + 1, i + 2, i);
    x[0].fromLight = 0;
    return x;
}

PathType pathType(std::span<const PathVertex> path) {
    PathType type;
    for (size_t i = 1; i + 1 < path.size(); ++i) type = type.withVertex(path[i].delta);
    return type;
}

std::optional<Vec2f> pathRaster(const Camera& camera, std::span<const PathVertex> path) {
    if (path.size() < 2) return std::nullopt;
    return camera.rasterOf(path[1].p);
}

std::string verifyPath(const RenderScene& scene, const Camera& camera,
                       std::span<const PathVertex> path, float tolerance) {
    std::vector<VertexDensities> want = recomputeDensities(scene, camera, path);
    auto close = [&](float a, float b) {
        return std::abs(a - b) <= tolerance * std::max(std::abs(a), std::abs(b));
    };
    for (size_t i = 1; i < path.size(); ++i) {
        bool isLight = i + 1 == path.size();
        // Nothing samples a delta light from the camera side: its fromEye is unused.
        bool eyeMatters = !isLight || isHittableLight(lightOf(scene, path[i]));
        if (eyeMatters && !close(path[i].pdfFromEye, want[i].fromEye))
            return "vertex " + std::to_string(i) + ": pdfFromEye " +
                   std::to_string(path[i].pdfFromEye) + ", recomputed " +
                   std::to_string(want[i].fromEye);
        if (!close(path[i].pdfFromLight, want[i].fromLight))
            return "vertex " + std::to_string(i) + ": pdfFromLight " +
                   std::to_string(path[i].pdfFromLight) + ", recomputed " +
                   std::to_string(want[i].fromLight);
    }
    return {};
}

namespace {

/// One serialised vertex: kind, light index, then either (mesh, triangle, barycentrics) or a
/// position.
struct PackedVertex {
    uint8_t kind;
    uint8_t pad[3];
    int32_t light;
    uint32_t mesh, triangle;
    float a, b, c;   // barycentrics (u, v, unused) or position
    uint32_t check;  // a constant, to reject garbage
};
static_assert(sizeof(PackedVertex) == 32);
constexpr uint32_t kPackedCheck = 0x50415448;  // "PATH"

}  // namespace

std::vector<uint8_t> serializePath(std::span<const PathVertex> path) {
    std::vector<uint8_t> out(path.size() * sizeof(PackedVertex));
    for (size_t i = 0; i < path.size(); ++i) {
        const PathVertex& v = path[i];
        PackedVertex pv{};
        pv.kind = uint8_t(v.kind);
        pv.light = v.light;
        pv.check = kPackedCheck;
        bool onSurface = v.isSurface() || !isBlack(v.ng);
        if (onSurface) {
            pv.mesh = v.hit.mesh;
            pv.triangle = v.hit.triangle;
            pv.a = v.hit.barycentric.x;
            pv.b = v.hit.barycentric.y;
        } else {
            pv.mesh = UINT32_MAX;
            pv.a = v.p.x;
            pv.b = v.p.y;
            pv.c = v.p.z;
        }
        std::memcpy(out.data() + i * sizeof(PackedVertex), &pv, sizeof pv);
    }
    return out;
}

namespace {

/// The surface point a serialised vertex names; std::invalid_argument for a mesh or triangle the
/// scene does not have (found by tests/fuzz/fuzz_chain_plan: hitAt's std::out_of_range escaped).
SurfaceHit hitOf(const RenderScene& scene, uint32_t mesh, uint32_t triangle, Vec2f barycentric,
                 size_t vertex) {
    try {
        return scene.hitAt(mesh, triangle, barycentric);
    } catch (const std::out_of_range&) {
        throw std::invalid_argument("not a serialised path (vertex " + std::to_string(vertex) +
                                    ": no mesh " + std::to_string(mesh) + " triangle " +
                                    std::to_string(triangle) + " in this scene)");
    }
}

}  // namespace

std::vector<PathVertex> deserializePath(const RenderScene& scene, const Camera& camera,
                                        std::span<const uint8_t> bytes) {
    if (bytes.size() % sizeof(PackedVertex) != 0 || bytes.size() < 2 * sizeof(PackedVertex))
        throw std::invalid_argument("not a serialised path (size)");
    std::vector<PathVertex> path(bytes.size() / sizeof(PackedVertex));
    auto kindAt = [&](size_t i) { return bytes[i * sizeof(PackedVertex)]; };
    if (kindAt(0) != uint8_t(VertexKind::Camera) ||
        kindAt(path.size() - 1) != uint8_t(VertexKind::Light))
        throw std::invalid_argument("not a serialised path (ends)");
    for (size_t i = 0; i < path.size(); ++i) {
        PackedVertex pv;
        std::memcpy(&pv, bytes.data() + i * sizeof(PackedVertex), sizeof pv);
        if (pv.check != kPackedCheck || pv.kind > uint8_t(VertexKind::Surface))
            throw std::invalid_argument("not a serialised path (vertex " + std::to_string(i) + ")");
        PathVertex& v = path[i];
        v.kind = VertexKind(pv.kind);
        v.light = pv.light;
        v.beta = Rgb(1.0f);
        if (!std::isfinite(pv.a) || !std::isfinite(pv.b) || !std::isfinite(pv.c))
            throw std::invalid_argument("not a serialised path (vertex " + std::to_string(i) +
                                        ": not a finite point)");
        if (pv.mesh != UINT32_MAX) {
            v.hit = hitOf(scene, pv.mesh, pv.triangle, {pv.a, pv.b}, i);
            v.p = v.hit.p;
            v.ng = v.hit.ng;
        } else {
            v.p = {pv.a, pv.b, pv.c};
        }
        if (v.kind == VertexKind::Light &&
            (v.light < 0 || size_t(v.light) >= scene.lights().size()))
            throw std::invalid_argument("not a serialised path (light index)");
        if (v.kind == VertexKind::Light) {
            const Light& l = scene.lights()[size_t(v.light)];
            v.delta = !cameraCanConnectTo(l);
            v.atInfinity = std::holds_alternative<EnvironmentLight>(l);
        }
    }
    // BSDFs and Dirac flags need the direction a vertex is seen from (opaque lobes mirror).
    for (size_t i = 1; i + 1 < path.size(); ++i) {
        PathVertex& v = path[i];
        if (!v.isSurface()) throw std::invalid_argument("not a serialised path (inner vertex)");
        v.bsdf = scene.bsdfAt(v.hit);
        v.delta = BoundBsdf(v.bsdf, unitTo(v, path[i - 1])).isDelta();
    }
    std::vector<VertexDensities> d = recomputeDensities(scene, camera, path);
    for (size_t i = 0; i < path.size(); ++i) {
        path[i].pdfFromEye = d[i].fromEye;
        path[i].pdfFromLight = d[i].fromLight;
    }
    return path;
}

}  // namespace partita
