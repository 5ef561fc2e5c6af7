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
    int n = x.size(), s = firstNonDirac(x, 1);
    Vec2f raster = perturbRaster(x.raster, pixels_, {rng.nextFloat(), rng.nextFloat()});
    if (!camera_.inImportanceSupport(raster)) return false;
    y.vertices.clear();
    y.vertices.reserve(size_t(n));
    y.vertices.push_back(x[0]);
    Vec3f w = normalize(camera_.generateRay(raster).d);
    if (retraceChain(scene_, x, x[0], w, 1, +1, y.vertices, rays) != s) return false;
    if (s < n - 1 && !reconnect(scene_, camera_, x, s, y.vertices, rays)) return false;
    if (!evaluatePath(scene_, camera_, y)) return false;
    reverseOverForward = retracedEyeDensity(camera_, x, s) / retracedEyeDensity(camera_, y, s);
    return true;
}

}  // namespace partita
