#include "path/mis.h"

namespace partita {

namespace {

/// A density of 0 marks a Dirac vertex (or one nothing else can generate): it counts as 1.
float remap(float pdf) { return pdf != 0 ? pdf : 1.0f; }

double heuristicTerm(double ratio, MisHeuristic h) {
    return h == MisHeuristic::Power ? ratio * ratio : ratio;
}

}  // namespace

bool strategyCanSample(std::span<const VertexDensities> x, int t, const MisPathInfo& info) {
    int n = int(x.size());
    if (t <= 0 || t > n || n < 2 || n - t > info.maxLightVertices) return false;
    if (t == n) return info.lightHittable;
    bool eyeEnd = t == 1 ? info.cameraConnectable : x[size_t(t - 1)].connectable;
    // The light vertex ends a next-event connection (t = n - 1) from any surface; only the
    // camera cannot connect to a light whose direction is a delta.
    bool lightEnd = x[size_t(t)].connectable || (t == n - 1 && t >= 2);
    return eyeEnd && lightEnd;
}

float misWeight(std::span<const VertexDensities> x, int t, const MisPathInfo& info,
                MisHeuristic heuristic) {
    int n = int(x.size());
    double sum = 0;
    // Strategies with fewer camera vertices: x_{t-1}, x_{t-2}, ... move to the light side.
    double ratio = 1;
    for (int k = t - 1; k >= 1; --k) {
        ratio *= double(remap(x[size_t(k)].fromLight)) / remap(x[size_t(k)].fromEye);
        if (strategyCanSample(x, k, info)) sum += heuristicTerm(ratio, heuristic);
    }
    // Strategies with more camera vertices: x_t, x_{t+1}, ... move to the camera side.
    ratio = 1;
    for (int k = t + 1; k <= n; ++k) {
        ratio *= double(remap(x[size_t(k - 1)].fromEye)) / remap(x[size_t(k - 1)].fromLight);
        if (strategyCanSample(x, k, info)) sum += heuristicTerm(ratio, heuristic);
    }
    return float(1 / (1 + sum));
}

}  // namespace partita
