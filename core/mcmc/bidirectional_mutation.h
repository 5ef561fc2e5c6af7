// Veach's bidirectional mutation (Veach 1997, sec. 11.4.2): delete a subpath of the current
// path and replace it with new vertices sampled from both of its ends and joined by one edge.
// It is the mutation that changes a path's length and type and keeps the chain ergodic.
//
// Edges are counted with one virtual edge beyond the light vertex: deleting it deletes the light
// vertex too, and the new subpath then starts with a fresh point on a light. For a path of n
// vertices x0 .. x_{n-1}:
//   1. kd deleted edges, kd in [1, n], with probability pd(kd) (deletionWeights, renormalised);
//   2. the first deleted edge l uniform in [0, min(n - kd, n - 2)]: x0 .. x_l and
//      x_{l+kd} .. x_{n-1} are kept (the pinhole x0 always is, the light never ends the camera
//      side);
//   3. ka added edges with probability pa(|ka - kd|) (additionWeights, both signs, renormalised
//      over the lengths the maximum depth allows): ka - 1 new vertices;
//   4. i of them from the camera side (BSDF sampling from x_l, or a fresh camera ray when l = 0),
//      the rest from the light side (a fresh light vertex first when it was deleted), i uniform
//      in [0, ka - 1]; all from the camera side when only the light vertex is kept (its
//      emission is not resampled alone);
//   5. one connection edge between the two ends, with a shadow ray; or, when the light vertex
//      was deleted and all new vertices come from the camera side, none: the camera side must
//      end on an area light or the environment (BDPT's s = 0).
// T(x->y) = pd(kd) / #l * pa(ka | kd) * (1 / #splits) * sum over the splits j of the
// density of sampling the new vertices that way (the sum: any split could have made y); T(y->x)
// deletes the new vertices of y and restores those of x with the same formula.
#pragma once

#include <vector>

#include "mcmc/mutation.h"

namespace partita {

class Camera;
class RenderScene;

struct BidirectionalSettings {
    /// pd(kd) for kd = 1, 2, ...; past the end each weight halves (Veach: 0.25, 0.5, 2^-k).
    std::vector<double> deletionWeights{0.25, 0.5, 0.125, 0.0625};
    /// pa by |ka - kd| = 0, 1, ...; each sign of a non-zero difference gets it; past the end
    /// each weight halves. The same length is the likeliest.
    std::vector<double> additionWeights{0.5, 0.15, 0.05, 0.025};
};

class BidirectionalMutation : public Mutation {
  public:
    BidirectionalMutation(const RenderScene& scene, const Camera& camera, int maxDepth,
                          BidirectionalSettings settings = {});

    std::string name() const override { return "bidirectional"; }
    bool appliesTo(const MarkovPath& x) const override { return x.size() >= 2; }
    bool propose(const MarkovPath& x, Rng& rng, MarkovPath& y, double& reverseOverForward,
                 uint64_t& rays) override;

    /// pd(kd) for a path of n vertices (n deletable edges); pa(ka | kd) given the kept vertices
    /// and whether the light vertex was deleted. Public for the tests.
    double deletionProbability(int kd, int n) const;
    double additionProbability(int ka, int kd, int kept, bool lightDeleted) const;

  private:
    /// The kept ends of a path of n vertices: x0 .. x_l and x_{l+k} .. (k deleted edges).
    struct Cut {
        int l, k;
    };
    /// Split range of a segment of k edges: the numbers i of camera-side vertices allowed.
    struct Splits {
        int first, last;
        int count() const { return last - first + 1; }
    };
    Splits splits(int n, Cut cut) const;
    /// The number of first deleted edges l possible for kd deleted edges of n.
    static int cutPositions(int kd, int n);
    /// The settings' weight of index i, its halving tail included.
    double deletionWeight(int i) const;
    double additionWeight(int i) const;
    bool endsOnHittableLight(const std::vector<PathVertex>& x) const;
    /// sum over the splits of the density of sampling path x's segment `cut` (step 4 above).
    double segmentDensity(const std::vector<PathVertex>& x, Cut cut) const;
    /// The proposal density of path x's segment given the rest: steps 1-4.
    double transitionDensity(const std::vector<PathVertex>& x, int nFrom, Cut cutFrom,
                             Cut cutTo) const;
    bool sampleSegment(const MarkovPath& x, Cut cut, int ka, int eyeCount, Rng& rng,
                       std::vector<PathVertex>& out, uint64_t& rays) const;

    const RenderScene& scene_;
    const Camera& camera_;
    int maxDepth_;
    BidirectionalSettings settings_;
    /// The settings' weights with their halving tails spelt out for every index a path of
    /// maxDepth can ask (a proposal sums them over every length, twice).
    std::vector<double> deletionTable_, additionTable_;
};

}  // namespace partita
