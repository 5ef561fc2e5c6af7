#include "guide/guided_perturbation.h"

#include <cmath>

#include "camera.h"
#include "mcmc/path_edits.h"

namespace partita {

namespace {

/// The pixel holding raster position r; false when r is outside the image's pixels.
bool pixelOf(Vec2f r, int width, int height, int& x, int& y) {
    x = int(std::floor(r.x));
    y = int(std::floor(r.y));
    return x >= 0 && y >= 0 && x < width && y < height;
}

}  // namespace

GuidedPerturbation::GuidedPerturbation(const RenderScene& scene, const Camera& camera,
                                       const ImageGuide& guide,
                                       const std::vector<PixelOffset>& delta,
                                       PerturbationRange lensPixels, bool throughSpecular)
    : scene_(scene),
      camera_(camera),
      guide_(guide),
      delta_(delta),
      lanes_(delta),
      opposite_(oppositeOffsets(delta)),
      lens_(scene, camera, lensPixels),
      throughSpecular_(throughSpecular) {}

const CandidateWeights& GuidedPerturbation::candidatesAt(int x, int y, const PathVertex& anchor) {
    for (int i = 0; i < 2; ++i) {
        CachedCandidates& c = cache_[i];
        if (c.x == x && c.y == y && c.anchor == anchor.p && c.anchorNormal == anchor.ng) {
            ++reused_;
            older_ = 1 - i;  // least recently used: the next computation keeps this one
            return c.weights;
        }
    }
    ++computed_;
    CachedCandidates& slot = cache_[older_];
    older_ = 1 - older_;
    slot.x = x;
    slot.y = y;
    slot.anchor = anchor.p;
    slot.anchorNormal = anchor.ng;
    guide_.candidates(lanes_, x, y, anchor, slot.weights);
    return slot.weights;
}

bool GuidedPerturbation::propose(const MarkovPath& x, Rng& rng, MarkovPath& y,
                                 double& reverseOverForward, uint64_t& rays) {
    lastSumRatio_ = 1;
    int n = x.size(), s = firstNonDirac(x, 1);
    // x_s the light (E S* L), or seen through a specular chain the guide may not follow.
    if (s == n - 1 || (s > 1 && !throughSpecular_))
        return lens_.propose(x, rng, y, reverseOverForward, rays);
    const PathVertex& anchor = x[s + 1];
    int px, py;
    if (!pixelOf(x.raster, guide_.width(), guide_.height(), px, py)) return false;
    // The cache evicts the least recently used slot: atP survives the lookup of atQ below.
    const CandidateWeights& atP = candidatesAt(px, py, anchor);
    int k = chooseCandidate(atP, rng.nextFloat());
    if (k < 0) return false;
    int qx = px + delta_[size_t(k)].dx, qy = py + delta_[size_t(k)].dy;
    Vec2f raster{float(qx) + rng.nextFloat(), float(qy) + rng.nextFloat()};

    y.vertices.clear();
    y.vertices.push_back(x[0]);
    Vec3f w = normalize(camera_.generateRay(raster).d);
    if (retraceChain(scene_, x, x[0], w, 1, +1, y.vertices, rays) != s) return false;
    if (!reconnect(scene_, camera_, x, s, y.vertices, rays)) return false;
    if (!evaluatePath(scene_, camera_, y)) return false;
    // The state's own raster decides its pixel (as it will when it is current); a rounding
    // across the pixel's edge is a rejection, never a density of the wrong pixel.
    int yx, yy;
    if (!pixelOf(y.raster, guide_.width(), guide_.height(), yx, yy) || yx != qx || yy != qy)
        return false;
    const CandidateWeights& atQ = candidatesAt(qx, qy, anchor);
    double choice = guidedProposalRatio(atP, atQ, k, opposite_[size_t(k)]);
    lastSumRatio_ = atQ.sum / atP.sum;
    reverseOverForward =
        choice * retracedEyeDensity(camera_, x, s) / retracedEyeDensity(camera_, y, s);
    return true;
}

}  // namespace partita
