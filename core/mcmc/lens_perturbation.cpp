#include "mcmc/lens_perturbation.h"

#include "camera.h"
#include "mcmc/path_edits.h"

namespace partita {

bool LensPerturbation::appliesTo(const MarkovPath& x) const {
    int n = x.size(), s = firstNonDirac(x, 1);
    if (s < 1) return false;
    return s == n - 1 || connectable(camera_, x[s], x[s + 1], s + 1 == n - 1);
}

bool LensPerturbation::propose(const MarkovPath& x, Rng& rng, MarkovPath& y,
                               double& reverseOverForward, uint64_t& rays) {
    int n = x.size();
    int s = retraceLensPrefix(scene_, camera_, x, pixels_, rng, y.vertices, rays);
    if (s < 0) return false;
    if (s < n - 1 && !reconnect(scene_, camera_, x, s, y.vertices, rays)) return false;
    if (!evaluatePath(scene_, camera_, y)) return false;
    reverseOverForward = retracedEyeDensity(camera_, x, s) / retracedEyeDensity(camera_, y, s);
    return true;
}

int retraceLensPrefix(const RenderScene& scene, const Camera& camera, const MarkovPath& x,
                      const PerturbationRange& pixels, Rng& rng, std::vector<PathVertex>& y,
                      uint64_t& rays) {
    Vec2f raster = perturbRaster(x.raster, pixels, {rng.nextFloat(), rng.nextFloat()});
    if (!camera.inImportanceSupport(raster)) return -1;
    y.clear();
    y.reserve(x.vertices.size());
    y.push_back(x[0]);
    Vec3f w = normalize(camera.generateRay(raster).d);
    return retraceChain(scene, x, x[0], w, 1, +1, y, rays);
}

}  // namespace partita
