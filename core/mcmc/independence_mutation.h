// The independence (large-step) mutation (issue #22 item 2): a fresh path y drawn by a random
// BDPT strategy, independent of the current path x, accepted with the exact ratio
//     a(x -> y) = min(1, f(y) p(x) / (f(x) p(y)))
// (Metropolis-Hastings with T(x->y) = p(y): Tierney's independence sampler), p the density of
// the whole path under the proposal. It can leave any path in one step: the chains' way out of
// types their local mutations cannot leave (specular-sandwiched ones, docs/mlt-study.md).
//
// Sampling: the vertex count n uniform over the allowed counts (every n in [2, maxDepth + 2],
// or a given subset: a chain's restriction may exclude lengths), the camera vertex count t
// (strategy (s, t), s = n - t) with probability c_t = kCameraOnlyShare [t = n] + (1 -
// kCameraOnlyShare) / n, the camera and light subpaths traced to exactly t and s vertices (no
// Russian roulette; a camera ray through a raster position uniform over the importance support,
// path_edits.h; s = 1 with t >= 2 samples the light vertex by next-event estimation), then
// connection (s, t) (path/connection.h, unweighted). Its density is the mixture over the
// strategies that can produce y (the MIS-combined density, one-sample MIS with weights c_t):
//     p(y) = 1 / #n * sum over t of c_t p_t(y),
// p_t the product of the camera-side densities of y_1 .. y_{t-1} and the light-side ones of
// y_t .. y_{n-1} (recomputeDensities with Dirac vertices as coefficients, as f). A strategy
// that cannot produce y (a connection at a Dirac vertex, s = 0 on a light no ray can hit) adds
// nothing. A proposal outside the chain's restriction has f = 0 there and is rejected by the
// chain (markov_chain.h).
//
// Why s = 0 gets a share of its own: a path whose diffuse vertices all sit between specular ones
// (bathroom's LSSSSDSSSSSSSE, pool's LSDSDSE; docs/mlt-study.md "Suspicious" 2) has no
// connectable edge, so s = 0 is its only strategy; with t uniform its p(x) would be n times
// smaller than a diffuse path's, its f / p n times larger, and a chain there would reject every
// fresh path for that much longer. The share keeps every other strategy within a factor of two.
#pragma once

#include <vector>

#include "mcmc/mutation.h"
#include "path/path_vertex.h"

namespace partita {

class Camera;
class RenderScene;

class IndependenceMutation : public Mutation {
  public:
    /// The share of proposals that trace the whole path from the camera (s = 0).
    static constexpr double kCameraOnlyShare = 0.5;

    /// `vertexCounts`: the path lengths (in vertices) proposed; empty: all of [2, maxDepth + 2].
    IndependenceMutation(const RenderScene& scene, const Camera& camera, int maxDepth,
                         std::vector<int> vertexCounts = {});

    std::string name() const override { return "independence"; }
    bool appliesTo(const MarkovPath& x) const override { return x.size() >= 2; }
    /// y fresh; reverseOverForward = p(x) / p(y).
    bool propose(const MarkovPath& x, Rng& rng, MarkovPath& y, double& reverseOverForward,
                 uint64_t& rays) override;

    /// A fresh path, evaluated (false when the strategy produced nothing that carries light).
    bool sample(Rng& rng, MarkovPath& y, uint64_t& rays) const;
    /// p(y) of the header, per unit of the path's area measure.
    double density(const std::vector<PathVertex>& y) const;

  private:
    /// c_t of the header for a path of n vertices.
    static double strategyProbability(int t, int n);
    /// Whether strategy t (camera vertices) can produce path p.
    bool canSample(const std::vector<PathVertex>& p, int t) const;
    bool allowsVertexCount(int n) const;

    const RenderScene& scene_;
    const Camera& camera_;
    std::vector<int> vertexCounts_;  // sorted, within [2, maxDepth + 2]
};

}  // namespace partita
