#include "mcmc/bidirectional_mutation.h"

#include <algorithm>
#include <climits>
#include <cmath>

#include "camera.h"
#include "light_emission.h"
#include "mcmc/path_edits.h"
#include "path/path.h"
#include "path/random_walk.h"
#include "render_scene.h"

namespace partita {

namespace {

/// weights[i], then halving past the end.
double halvingWeight(const std::vector<double>& weights, int i) {
    if (i < int(weights.size())) return weights[size_t(i)];
    double w = weights.empty() ? 1.0 : weights.back();
    return w * std::ldexp(1.0, -(i - int(weights.size()) + 1));
}

/// halvingWeight for i = 0 .. count - 1.
std::vector<double> halvingTable(const std::vector<double>& weights, int count) {
    std::vector<double> table(size_t(std::max(count, 0)));
    for (int i = 0; i < count; ++i) table[size_t(i)] = halvingWeight(weights, i);
    return table;
}

/// Index in [0, count) drawn with probability weight(i) / sum.
template <typename Weight>
int sampleDiscrete(int count, Weight&& weight, float u) {
    double total = 0;
    for (int i = 0; i < count; ++i) total += weight(i);
    double target = double(u) * total, running = 0;
    for (int i = 0; i < count; ++i) {
        running += weight(i);
        if (target < running) return i;
    }
    return count - 1;
}

/// Whether v[from, end) are all surfaces.
bool allSurfaces(const std::vector<PathVertex>& v, size_t from, size_t end) {
    for (size_t i = from; i < end; ++i)
        if (!v[i].isSurface()) return false;
    return true;
}

}  // namespace

BidirectionalMutation::BidirectionalMutation(const RenderScene& scene, const Camera& camera,
                                             int maxDepth, BidirectionalSettings settings)
    : scene_(scene),
      camera_(camera),
      maxDepth_(maxDepth),
      settings_(std::move(settings)),
      // A path has at most maxDepth + 2 vertices: kd - 1 and |ka - kd| stay below maxDepth + 4.
      deletionTable_(halvingTable(settings_.deletionWeights, maxDepth + 4)),
      additionTable_(halvingTable(settings_.additionWeights, maxDepth + 4)) {}

double BidirectionalMutation::deletionWeight(int i) const {
    return i < int(deletionTable_.size()) ? deletionTable_[size_t(i)]
                                          : halvingWeight(settings_.deletionWeights, i);
}

double BidirectionalMutation::additionWeight(int i) const {
    return i < int(additionTable_.size()) ? additionTable_[size_t(i)]
                                          : halvingWeight(settings_.additionWeights, i);
}

bool BidirectionalMutation::endsOnHittableLight(const std::vector<PathVertex>& x) const {
    const PathVertex& last = x.back();
    return last.kind == VertexKind::Light && last.light >= 0 &&
           isHittableLight(scene_.lights()[size_t(last.light)]);
}

double BidirectionalMutation::deletionProbability(int kd, int n) const {
    if (kd < 1 || kd > n) return 0;
    double total = 0;
    for (int k = 1; k <= n; ++k) total += deletionWeight(k - 1);
    return deletionWeight(kd - 1) / total;
}

double BidirectionalMutation::additionProbability(int ka, int kd, int kept,
                                                  bool lightDeleted) const {
    // The new path has kept + ka - 1 vertices, at most maxDepth scattering ones.
    int minKa = lightDeleted ? 2 : 1, maxKa = maxDepth_ + 3 - kept;
    if (ka < minKa || ka > maxKa) return 0;
    double total = 0;
    for (int k = minKa; k <= maxKa; ++k) total += additionWeight(std::abs(k - kd));
    return additionWeight(std::abs(ka - kd)) / total;
}

BidirectionalMutation::Splits BidirectionalMutation::splits(int n, Cut cut) const {
    int added = cut.k - 1;
    // A kept light vertex alone is not extended (its emission direction is not resampled
    // without its position): everything comes from the camera side and connects to it.
    if (cut.l + cut.k == n - 1) return {added, added};
    // When the light vertex was deleted, i = added means the camera side ends on a light.
    return {0, added};
}

int BidirectionalMutation::cutPositions(int kd, int n) {
    // l in [0, n - kd], and l <= n - 2: the camera side never ends at the old light vertex.
    return std::min(n - kd, n - 2) + 1;
}

double BidirectionalMutation::segmentDensity(const std::vector<PathVertex>& x, Cut cut) const {
    int n = int(x.size());
    std::vector<VertexDensities> d =
        recomputeDensities(scene_, camera_, x, DiracVertices::Coefficient);
    float cameraScale = cameraSupportScale(camera_);
    auto eyeDensity = [&](int v) {
        return double(d[size_t(v)].fromEye) * (v == 1 ? cameraScale : 1.0f);
    };
    Splits range = splits(n, cut);
    bool lightDeleted = cut.l + cut.k == n;
    double sum = 0;
    for (int i = range.first; i <= range.last; ++i) {
        int eyeEnd = cut.l + i, lightEnd = eyeEnd + 1;
        bool feasible = lightEnd == n ? lightDeleted && endsOnHittableLight(x)
                                      : connectable(camera_, x[size_t(eyeEnd)], x[size_t(lightEnd)],
                                                    lightEnd == n - 1);
        if (!feasible) continue;
        double p = 1;
        for (int v = cut.l + 1; v <= eyeEnd; ++v) p *= eyeDensity(v);
        for (int v = lightEnd; v < cut.l + cut.k; ++v) p *= d[size_t(v)].fromLight;
        sum += p;
    }
    return sum / range.count();
}

double BidirectionalMutation::transitionDensity(const std::vector<PathVertex>& x, int nFrom,
                                                Cut cutFrom, Cut cutTo) const {
    int kept = nFrom - cutFrom.k + 1;
    bool lightDeleted = cutFrom.l + cutFrom.k == nFrom;
    double choice = deletionProbability(cutFrom.k, nFrom) / double(cutPositions(cutFrom.k, nFrom)) *
                    additionProbability(cutTo.k, cutFrom.k, kept, lightDeleted);
    return choice > 0 ? choice * segmentDensity(x, cutTo) : 0;
}

bool BidirectionalMutation::sampleSegment(const MarkovPath& x, Cut cut, int ka, int eyeCount,
                                          Rng& rng, std::vector<PathVertex>& out,
                                          uint64_t& rays) const {
    int n = x.size();
    bool lightDeleted = cut.l + cut.k == n;
    int lightCount = ka - 1 - eyeCount;
    WalkSettings walk;
    walk.rouletteStartDepth = INT_MAX;
    // The camera side: x0 .. x_l, then eyeCount new vertices.
    std::vector<PathVertex> eye(x.vertices.begin(), x.vertices.begin() + cut.l + 1);
    if (eyeCount > 0) {
        if (cut.l == 0) {
            Vec2f raster = sampleSupportRaster(camera_, {rng.nextFloat(), rng.nextFloat()});
            walk.maxVertices = 1 + eyeCount;
            traceCameraSubpath(scene_, camera_, camera_.generateRay(raster), rng, walk, eye, rays);
        } else {
            extendSubpath(scene_, rng, TransportMode::Radiance, eyeCount, eye, rays);
        }
        if (int(eye.size()) != cut.l + 1 + eyeCount) return false;
    }
    bool eyeEndsOnLight = lightDeleted && lightCount == 0;
    if (eyeEndsOnLight) {
        // The camera side hit a light: that is the new path (strategy s = 0).
        PathVertex& end = eye.back();
        if (end.isSurface() && end.light >= 0) end = asLightVertex(scene_, end);
        if (!endsOnHittableLight(eye) || !allSurfaces(eye, size_t(cut.l + 1), eye.size() - 1))
            return false;
        out = std::move(eye);
        return true;
    }
    if (!allSurfaces(eye, size_t(cut.l + 1), eye.size())) return false;
    // The light side, stored light first: the kept suffix reversed (or a fresh light vertex),
    // then lightCount new vertices.
    std::vector<PathVertex> light;
    if (lightDeleted) {
        walk.maxVertices = lightCount;
        traceLightSubpath(scene_, rng, walk, light, rays);
        if (int(light.size()) != lightCount || !allSurfaces(light, 1, light.size())) return false;
    } else {
        light.assign(x.vertices.rbegin(), x.vertices.rend() - (cut.l + cut.k));
        size_t kept = light.size();
        if (lightCount > 0) {
            extendSubpath(scene_, rng, TransportMode::Importance, lightCount, light, rays);
            if (light.size() != kept + size_t(lightCount) ||
                !allSurfaces(light, kept, light.size()))
                return false;
        }
    }
    if (!lightDeleted && light.size() == 1 && isInfiniteLightVertex(scene_, light[0]))
        light[0] = reanchoredLight(scene_, light[0], x[n - 2].p, eye.back().p);
    const PathVertex &a = eye.back(), &b = light.back();
    if (!connectable(camera_, a, b, light.size() == 1) || !visible(scene_, a, b, rays))
        return false;
    out = std::move(eye);
    out.insert(out.end(), light.rbegin(), light.rend());
    return true;
}

bool BidirectionalMutation::propose(const MarkovPath& x, Rng& rng, MarkovPath& y,
                                    double& reverseOverForward, uint64_t& rays) {
    int n = x.size();
    // Steps 1-4 of the header: what to delete, how much to add, how to split it.
    int kd = 1 + sampleDiscrete(
                     n, [&](int i) { return deletionWeight(i); }, rng.nextFloat());
    int l = int(rng.nextBounded(uint32_t(cutPositions(kd, n))));
    Cut cutX{l, kd};
    int kept = n - kd + 1;
    bool lightDeleted = l + kd == n;
    int minKa = lightDeleted ? 2 : 1, maxKa = maxDepth_ + 3 - kept;
    float uKa = rng.nextFloat();
    if (maxKa < minKa) return false;
    int ka = minKa + sampleDiscrete(
                         maxKa - minKa + 1,
                         [&](int i) { return additionWeight(std::abs(minKa + i - kd)); }, uKa);
    Cut cutY{l, ka};
    int nY = kept + ka - 1;
    Splits range = splits(nY, cutY);
    if (range.count() <= 0) return false;
    int eyeCount = range.first + int(rng.nextBounded(uint32_t(range.count())));
    if (!sampleSegment(x, cutX, ka, eyeCount, rng, y.vertices, rays)) return false;
    if (!evaluatePath(scene_, camera_, y)) return false;
    double forward = transitionDensity(y.vertices, n, cutX, cutY);
    double reverse = transitionDensity(x.vertices, nY, cutY, cutX);
    if (!(forward > 0)) return false;
    reverseOverForward = reverse / forward;
    return true;
}

}  // namespace partita
