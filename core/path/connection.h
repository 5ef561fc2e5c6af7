// Bidirectional connections: strategy (s, t) joins the first t vertices of a camera subpath with
// the first s of a light subpath into one complete path (Veach 1997, ch. 10), and evaluates its
// unweighted contribution f / p, its Heckbert type and its MIS weight.
//
//   s = 0       the camera subpath itself hits an area light;
//   s = 1       next-event estimation: a fresh point on a light, chosen by power;
//   t = 1       light tracing: the light subpath's vertex seen by the camera, splatted at its
//               raster position;
//   otherwise   an edge between camera vertex t-1 and light vertex s-1.
// The strategy's full path has the camera-first densities of mis.h: the subpaths' stored ones,
// with the four around the new edge recomputed for the directions the connection created.
#pragma once

#include <span>
#include <vector>

#include "math/vec.h"
#include "path/mis.h"
#include "path/path_vertex.h"
#include "path_type.h"
#include "rng.h"

namespace partita {

class Camera;
class RenderScene;

struct StrategySample {
    bool valid = false;  // false: the strategy produced nothing (blocked, black, impossible)
    Rgb value{0.0f};     // unweighted contribution f / p
    float weight = 0;    // MIS weight
    PathType type;
    Vec2f raster;  // t == 1: the raster position the contribution belongs to
    /// The chains' short-edge damping tau of the strategy's full path
    /// (path/short_edge_damping.h), 1 unless the connector was asked for it (dampShortEdges).
    float edgeDamping = 1;
};

class Connector {
  public:
    /// With `keepPaths`, each connection also assembles its complete path (lastPath); BDPT's
    /// inner loop needs only the densities and leaves it off.
    Connector(const RenderScene& scene, const Camera& camera, bool keepPaths = false)
        : scene_(scene), camera_(camera), keepPaths_(keepPaths) {}

    /// Weights only over a path tracer's strategies, emitter hits (s = 0) and next-event
    /// estimation (s = 1, t > 1), as the paper's pre-pass estimator; connect() must then only be
    /// called for those.
    void restrictToPathTracer() { pathTracer_ = true; }

    /// Each sample's edgeDamping computed with edges below `shortEdge` damped (the bootstrap's:
    /// b* is the integral of the chains' damped target).
    void dampShortEdges(float shortEdge) { shortEdge_ = shortEdge; }

    /// Strategy (s, t) of the subpaths (which must hold at least t and s vertices). For s == 1
    /// a light vertex is sampled with `rng`. `rays` counts the shadow rays. The weight is
    /// computed with `heuristic`, or is 1 when `weighted` is false (one strategy alone).
    StrategySample connect(std::span<const PathVertex> camera, std::span<const PathVertex> light,
                           int s, int t, Rng& rng, uint64_t& rays, bool weighted = true,
                           MisHeuristic heuristic = MisHeuristic::Power);

    /// The complete path of the last connect() call, camera first (x0 .. xM); for tests and the
    /// MCMC methods. Valid only when that call returned a valid sample and keepPaths is set.
    const std::vector<PathVertex>& lastPath() const { return path_; }
    /// Its densities as connect() computed them for the MIS weight.
    const std::vector<VertexDensities>& lastDensities() const { return densities_; }
    MisPathInfo lastPathInfo() const { return info_; }

  private:
    bool visible(const PathVertex& a, const PathVertex& b, uint64_t& rays) const;
    StrategySample emitterHit(std::span<const PathVertex> camera, int t);
    StrategySample nextEvent(std::span<const PathVertex> camera, int t, Rng& rng, uint64_t& rays);
    StrategySample lightTracing(std::span<const PathVertex> light, int s, uint64_t& rays);
    StrategySample edge(std::span<const PathVertex> camera, std::span<const PathVertex> light,
                        int s, int t, uint64_t& rays);
    /// path_ and densities_ from the first t camera and s light vertices; `light` last.
    void assemble(std::span<const PathVertex> camera, int t, std::span<const PathVertex> light,
                  int s);

    const RenderScene& scene_;
    const Camera& camera_;
    bool keepPaths_;
    bool pathTracer_ = false;
    float shortEdge_ = 0;    // dampShortEdges; 0: edgeDamping stays 1
    float edgeDamping_ = 1;  // of the last assemble()
    std::vector<PathVertex> path_;
    std::vector<VertexDensities> densities_;
    MisPathInfo info_;
};

/// The type of the path made of camera vertices x1 .. x_{t-1} then light vertices
/// l_{s-1} .. l1 (the light vertex itself and the camera are not scattering vertices).
PathType connectedType(std::span<const PathVertex> camera, int t, std::span<const PathVertex> light,
                       int s);

}  // namespace partita
