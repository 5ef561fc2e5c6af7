// Multiple importance sampling over the strategies of bidirectional path tracing (Veach 1997,
// ch. 10), from the area-measure densities stored on a path's vertices.
//
// A path x0 (camera) .. x_{n-1} (light) of n vertices can be sampled by n + 1 strategies, named
// here by t, the number of vertices taken from the camera subpath (s = n - t from the light):
// the strategy's density is p_t = prod_{i<t} fromEye(x_i) * prod_{i>=t} fromLight(x_i). Its
// weight (power heuristic, beta = 2) is p_t^2 / sum_k p_k^2 over the strategies k that can
// produce the path, computed with the ratios p_{k-1}/p_k = fromLight(x_{k-1})/fromEye(x_{k-1}).
//
// Which strategies can produce a path (and so enter the sum):
// - t = 0 never: the camera is a pinhole (or orthographic), no ray hits it;
// - t = 1 (light tracing) only for a connectable camera (a perspective pinhole) and a
//   connectable x1;
// - 1 < t < n: the connection x_{t-1} -- x_t needs both ends non-delta; its light end may be the
//   light vertex itself (t = n - 1, next-event estimation), which any light allows;
// - t = n (s = 0, the camera path hits the light) only for an area light.
// Densities at Dirac vertices are stored as 0 and count as 1 in the ratios: the delta appears in
// every strategy that can sample the path and cancels.
#pragma once

#include <span>

namespace partita {

/// One vertex's densities, as MIS needs them.
struct VertexDensities {
    float fromEye = 0, fromLight = 0;
    bool connectable = true;  // a connection edge may end here (not a Dirac vertex)
};

enum class MisHeuristic { Balance, Power };

struct MisPathInfo {
    bool cameraConnectable = true;  // a perspective pinhole: t = 1 strategies exist (if used)
    bool lightHittable = true;      // an area light: the t = n strategy exists
    /// Only strategies with at most this many light vertices are used: 1 makes the
    /// estimator a path tracer with next-event estimation and MIS (s = 0 and s = 1).
    int maxLightVertices = 1 << 30;
};

/// Whether strategy t can produce the path `x` (see above).
bool strategyCanSample(std::span<const VertexDensities> x, int t, const MisPathInfo& info);

/// The MIS weight of strategy t for the path `x`.
float misWeight(std::span<const VertexDensities> x, int t, const MisPathInfo& info,
                MisHeuristic heuristic = MisHeuristic::Power);

}  // namespace partita
