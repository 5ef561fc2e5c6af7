#include "mcmc/caustic_perturbation.h"

#include "camera.h"
#include "mcmc/path_edits.h"

namespace partita {

namespace {

/// x_a of the header, or -1: x1 diffuse, x2 .. x_{a-1} specular (at least one), x_a neither
/// Dirac nor at infinity (a surface, or an area, point or spot light).
int causticSource(const MarkovPath& x) {
    if (x.size() < 4 || x[1].delta || !x[2].delta) return -1;
    int a = firstNonDirac(x, 2);
    if (a < 3 || x[a].delta || x[a].atInfinity) return -1;
    return a;
}

}  // namespace

bool CausticPerturbation::appliesTo(const MarkovPath& x) const {
    return camera_.isConnectable() && causticSource(x) >= 0;
}

bool CausticPerturbation::propose(const MarkovPath& x, Rng& rng, MarkovPath& y,
                                  double& reverseOverForward, uint64_t& rays) {
    int a = causticSource(x);
    Vec3f old = normalize(x[a - 1].p - x[a].p);
    Vec3f turned = perturbDirection(old, angles_, {rng.nextFloat(), rng.nextFloat()});
    std::vector<PathVertex> chain;  // y_{a-1} .. y_1
    chain.reserve(size_t(a));
    if (retraceChain(scene_, x, x[a], turned, a - 1, -1, chain, rays) != 1) return false;
    if (!visible(scene_, chain.back(), x[0], rays)) return false;
    y.vertices.clear();
    y.vertices.reserve(x.vertices.size());
    y.vertices.push_back(x[0]);
    y.vertices.insert(y.vertices.end(), chain.rbegin(), chain.rend());
    y.vertices.insert(y.vertices.end(), x.vertices.begin() + a, x.vertices.end());
    if (!evaluatePath(scene_, camera_, y)) return false;
    reverseOverForward = retracedLightDensity(x, a) / retracedLightDensity(y, a);
    return true;
}

}  // namespace partita
