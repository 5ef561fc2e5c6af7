#include "mcmc/independence_mutation.h"

#include <algorithm>
#include <climits>

#include "camera.h"
#include "light_emission.h"
#include "mcmc/path_edits.h"
#include "path/connection.h"
#include "path/path.h"
#include "path/random_walk.h"
#include "render_scene.h"

namespace partita {

IndependenceMutation::IndependenceMutation(const RenderScene& scene, const Camera& camera,
                                           int maxDepth, std::vector<int> vertexCounts)
    : scene_(scene), camera_(camera) {
    if (vertexCounts.empty())
        for (int n = 2; n <= maxDepth + 2; ++n) vertexCounts.push_back(n);
    std::sort(vertexCounts.begin(), vertexCounts.end());
    vertexCounts.erase(std::unique(vertexCounts.begin(), vertexCounts.end()), vertexCounts.end());
    for (int n : vertexCounts)
        if (n >= 2 && n <= maxDepth + 2) vertexCounts_.push_back(n);
}

bool IndependenceMutation::allowsVertexCount(int n) const {
    return std::binary_search(vertexCounts_.begin(), vertexCounts_.end(), n);
}

bool IndependenceMutation::propose(const MarkovPath& x, Rng& rng, MarkovPath& y,
                                   double& reverseOverForward, uint64_t& rays) {
    if (!sample(rng, y, rays)) return false;
    double forward = density(y.vertices);
    if (!(forward > 0)) return false;
    // T(y->x) / T(x->y) = p(x) / p(y): the proposal does not look at the current path.
    reverseOverForward = density(x.vertices) / forward;
    return true;
}

bool IndependenceMutation::sample(Rng& rng, MarkovPath& y, uint64_t& rays) const {
    if (vertexCounts_.empty()) return false;
    int n = vertexCounts_[rng.nextBounded(uint32_t(vertexCounts_.size()))];
    float uCameraOnly = rng.nextFloat();
    int t = 1 + int(rng.nextBounded(uint32_t(n)));
    if (double(uCameraOnly) < kCameraOnlyShare) t = n;
    int s = n - t;
    WalkSettings walk;
    walk.rouletteStartDepth = INT_MAX;
    walk.maxVertices = t;
    Vec2f raster = sampleSupportRaster(camera_, {rng.nextFloat(), rng.nextFloat()});
    std::vector<PathVertex> eye, light;
    traceCameraSubpath(scene_, camera_, camera_.generateRay(raster), rng, walk, eye, rays);
    if (int(eye.size()) != t) return false;
    if (s == 1 && t >= 2) {
        light.resize(1);  // next-event estimation samples its own light vertex
    } else if (s >= 1) {
        walk.maxVertices = s;
        traceLightSubpath(scene_, rng, walk, light, rays);
        if (int(light.size()) != s) return false;
    }
    Connector connector(scene_, camera_, /*keepPaths=*/true);
    StrategySample c = connector.connect(eye, light, s, t, rng, rays, /*weighted=*/false);
    if (!c.valid) return false;
    y.vertices = connector.lastPath();
    return evaluatePath(scene_, camera_, y);
}

double IndependenceMutation::density(const std::vector<PathVertex>& p) const {
    int n = int(p.size());
    if (!allowsVertexCount(n)) return 0;
    std::vector<VertexDensities> d =
        recomputeDensities(scene_, camera_, p, DiracVertices::Coefficient);
    // Camera rays are uniform over the importance support, not the image (path_edits.h).
    float cameraScale = cameraSupportScale(camera_);
    double sum = 0;
    for (int t = 1; t <= n; ++t) {
        if (!canSample(p, t)) continue;
        double pt = 1;
        for (int i = 1; i < t; ++i) pt *= d[size_t(i)].fromEye * (i == 1 ? cameraScale : 1.0f);
        for (int i = t; i < n; ++i) pt *= d[size_t(i)].fromLight;
        sum += strategyProbability(t, n) * pt;
    }
    return sum / double(vertexCounts_.size());
}

double IndependenceMutation::strategyProbability(int t, int n) {
    return (1 - kCameraOnlyShare) / double(n) + (t == n ? kCameraOnlyShare : 0.0);
}

bool IndependenceMutation::canSample(const std::vector<PathVertex>& p, int t) const {
    int n = int(p.size());
    const PathVertex& last = p.back();
    if (t == n) return last.light >= 0 && isHittableLight(scene_.lights()[size_t(last.light)]);
    return connectable(camera_, p[size_t(t - 1)], p[size_t(t)], t == n - 1);
}

}  // namespace partita
