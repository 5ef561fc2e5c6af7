// One vertex of a light path, shared by BDPT and every MCMC method. Paths are stored camera
// first: x0 is the camera, x1 .. x_{M-1} scatter, x_M is on a light (DESIGN.md, paper Sec. 3).
//
// Densities are kept in area measure at the vertex and named by the direction of sampling:
// - pdfFromEye: the density of generating this vertex from its camera-side neighbour (by the
//   camera, or a BSDF sampled at x_{i-1} given x_{i-2});
// - pdfFromLight: the density of generating it from its light-side neighbour (by the light, or a
//   BSDF sampled at x_{i+1} given x_{i+2}).
// A camera subpath computes pdfFromEye as it goes and pdfFromLight once the next vertex is known;
// a light subpath the other way round. At Dirac (specular) vertices both are left 0: the delta
// cancels between all strategies that can sample the path (see mis.h).
#pragma once

#include "bsdf.h"
#include "math/vec.h"
#include "surface_hit.h"

namespace partita {

enum class VertexKind : uint8_t { Camera, Light, Surface };

struct PathVertex {
    VertexKind kind = VertexKind::Surface;
    Vec3f p;
    /// Geometric normal of a surface or area-light vertex; zero where there is no surface (the
    /// camera, point, spot and directional lights), which then contributes no cosine.
    Vec3f ng;
    SurfaceHit hit;  // surfaces and area lights
    Bsdf bsdf;       // surfaces
    int light = -1;  // light vertices: the light's index; surfaces: the area light hit, or -1
    /// A Dirac BSDF (the vertex is "S" in the Heckbert string), or a light the camera cannot
    /// connect to (directional: a delta direction; the environment): no connection edge from a
    /// pinhole can end here.
    bool delta = false;
    /// An environment vertex, infinitely far: `p` is a stand-in point beyond the scene, and
    /// densities of reaching it are solid angle densities (there is no area to convert to).
    bool atInfinity = false;
    /// Throughput of the subpath up to and including this vertex: f / p of the partial path
    /// (for a light subpath, with Le and the light's densities included).
    Rgb beta{0.0f};
    float pdfFromEye = 0, pdfFromLight = 0;

    bool isSurface() const { return kind == VertexKind::Surface; }
    /// Whether a connection (a deterministic edge) may end here.
    bool isConnectable() const { return !delta; }
};

/// |cos| of the unit direction w at v's geometric normal; 1 where v has no surface.
inline float geometricCos(const PathVertex& v, Vec3f w) {
    return isBlack(v.ng) ? 1.0f : absDot(v.ng, w);
}

/// A solid-angle density of leaving `from` towards `to`, converted to area measure at `to`.
inline float solidAngleToArea(float pdf, const PathVertex& from, const PathVertex& to) {
    if (to.atInfinity) return pdf;
    Vec3f d = to.p - from.p;
    float dist2 = lengthSquared(d);
    if (!(dist2 > 0)) return 0;
    return pdf * geometricCos(to, d / std::sqrt(dist2)) / dist2;
}

}  // namespace partita
