#include "mcmc/multi_chain_perturbation.h"

#include "camera.h"
#include "mcmc/lens_perturbation.h"
#include "mcmc/path_edits.h"

namespace partita {

namespace {

/// Whether the chain that ends at non-Dirac vertex c continues into a specular vertex (one
/// that is not the light: a Dirac light is reached by a connection).
bool continuesIntoDirac(const MarkovPath& x, int c) {
    return c + 1 < x.size() - 1 && x[c + 1].delta;
}

}  // namespace

bool MultiChainPerturbation::appliesTo(const MarkovPath& x) const {
    int s = firstNonDirac(x, 1);
    return s >= 1 && continuesIntoDirac(x, s);
}

bool MultiChainPerturbation::propose(const MarkovPath& x, Rng& rng, MarkovPath& y,
                                     double& reverseOverForward, uint64_t& rays) {
    int n = x.size();
    int c = retraceLensPrefix(scene_, camera_, x, pixels_, rng, y.vertices, rays);
    if (c < 0) return false;
    while (continuesIntoDirac(x, c)) {
        Vec3f old = normalize(x[c + 1].p - x[c].p);
        Vec3f turned = perturbDirection(old, angles_, {rng.nextFloat(), rng.nextFloat()});
        PathVertex from = y.vertices.back();
        c = retraceChain(scene_, x, from, turned, c + 1, +1, y.vertices, rays);
        if (c < 0) return false;
    }
    if (c < n - 1 && !reconnect(scene_, camera_, x, c, y.vertices, rays)) return false;
    if (!evaluatePath(scene_, camera_, y)) return false;
    reverseOverForward = retracedEyeDensity(camera_, x, c) / retracedEyeDensity(camera_, y, c);
    return true;
}

}  // namespace partita
