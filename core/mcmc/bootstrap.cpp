#include "mcmc/bootstrap.h"

#include <algorithm>
#include <cmath>

#include "camera.h"
#include "mcmc/path_edits.h"
#include "path/connection.h"
#include "render_scene.h"

namespace partita {

static_assert(sizeof(BootstrapCandidate) == 40, "the record size the comments and estimates use");

namespace {
constexpr uint64_t kBootstrapStream = 0x424f4f54ull << 32;  // "BOOT": apart from pixel streams
}

BootstrapSampler::BootstrapSampler(const RenderScene& scene, const Camera& camera, int maxDepth,
                                   uint64_t seed, StartupEstimator estimator)
    : scene_(scene), camera_(camera), maxDepth_(maxDepth), seed_(seed), estimator_(estimator) {
    // As BDPT: a camera subpath may end on an emitter one vertex further (s = 0).
    cameraWalk_.maxVertices = maxDepth + 2;
    lightWalk_.maxVertices = maxDepth + 1;
}

template <typename Visit>
void BootstrapSampler::forEachStrategy(uint64_t index, uint64_t& rays, bool keepPaths,
                                       Visit&& visit) const {
    Rng rng(seed_, kBootstrapStream + index);
    Vec2f raster = sampleSupportRaster(camera_, {rng.nextFloat(), rng.nextFloat()});
    std::vector<PathVertex> cameraPath, lightPath;
    traceCameraSubpath(scene_, camera_, camera_.generateRay(raster), rng, cameraWalk_, cameraPath,
                       rays);
    // A path tracer still draws the light subpath, so that both estimators consume the same
    // random numbers up to here (its next-event estimation samples its own light vertex).
    traceLightSubpath(scene_, rng, lightWalk_, lightPath, rays);
    Connector connector(scene_, camera_, keepPaths);
    bool pathTracer = estimator_ == StartupEstimator::PathTracer;
    if (pathTracer) connector.restrictToPathTracer();
    connector.dampShortEdges(scene_.shortEdge());  // b* of the chains' target
    int cameraCount = int(cameraPath.size()), lightCount = int(lightPath.size());
    int maxS = pathTracer ? 1 : std::max(lightCount, 1);
    for (int t = 1; t <= cameraCount; ++t)
        for (int s = 0; s <= maxS; ++s) {
            if (pathTracer && t == 1) continue;  // light tracing is not a path tracer's
            if (s + t < 2 || s + t - 2 > maxDepth_) continue;
            if (s > lightCount && !(s == 1 && t > 1)) continue;
            StrategySample c = connector.connect(cameraPath, lightPath, s, t, rng, rays);
            if (!c.valid || !(c.weight > 0)) continue;
            if (!visit(s, t, c, connector, raster)) return;
        }
}

double BootstrapSampler::sample(uint64_t index, std::vector<BootstrapCandidate>& out,
                                uint64_t& rays) const {
    // Camera rays are uniform over the support, not over the image: their true density is
    // directionPdf times this scale (path_edits.h), light tracing (t = 1) does not use them.
    float cameraScale = cameraSupportScale(camera_);
    double sum = 0;
    int width = camera_.width(), height = camera_.height();
    auto pixelOf = [&](Vec2f r) {
        int x = clamp(int(std::floor(r.x)), 0, width - 1);
        int y = clamp(int(std::floor(r.y)), 0, height - 1);
        return uint32_t(y) * uint32_t(width) + uint32_t(x);
    };
    forEachStrategy(
        index, rays, false, [&](int s, int t, const StrategySample& c, Connector&, Vec2f raster) {
            // f* / p with the chains' target, lum(f) tau (short_edge_damping.h): b* and the
            // starts are those of the target the chains sample.
            float weight =
                c.weight * luminance(c.value) * c.edgeDamping / (t >= 2 ? cameraScale : 1.0f);
            if (weight > 0 && std::isfinite(weight)) {
                out.push_back({index, uint16_t(s), uint16_t(t), weight, c.type,
                               pixelOf(t >= 2 ? raster : c.raster)});
                sum += weight;
            }
            return true;
        });
    return sum;
}

bool BootstrapSampler::regenerate(const BootstrapCandidate& candidate, MarkovPath& out,
                                  uint64_t& rays) const {
    bool found = false;
    forEachStrategy(candidate.sample, rays, true,
                    [&](int s, int t, const StrategySample&, Connector& connector, Vec2f) {
                        if (s != candidate.s || t != candidate.t) return true;
                        out.vertices = connector.lastPath();
                        found = true;
                        return false;
                    });
    return found && evaluatePath(scene_, camera_, out);
}

namespace {

/// Systematic resampling over n weights weight(0..n-1).
template <class Weight>
std::vector<size_t> resample(size_t n, Weight weight, size_t count, Rng& rng) {
    std::vector<size_t> chosen;
    double total = 0;
    for (size_t j = 0; j < n; ++j) total += weight(j);
    if (!(total > 0) || count == 0) return chosen;
    double u = rng.nextFloat(), running = 0;
    size_t i = 0;
    for (size_t k = 0; k < count; ++k) {
        double target = (double(k) + u) / double(count) * total;
        while (i + 1 < n && running + weight(i) <= target) running += weight(i++);
        chosen.push_back(i);
    }
    return chosen;
}

}  // namespace

std::vector<size_t> resampleCandidates(const std::vector<BootstrapCandidate>& candidates,
                                       size_t count, Rng& rng) {
    return resample(
        candidates.size(), [&](size_t j) { return double(candidates[j].weight); }, count, rng);
}

std::vector<size_t> resampleCandidates(const std::vector<BootstrapCandidate>& candidates,
                                       const std::vector<uint32_t>& members, size_t count,
                                       Rng& rng) {
    return resample(
        members.size(), [&](size_t j) { return double(candidates[members[j]].weight); }, count,
        rng);
}

}  // namespace partita
