// Veach's multi-chain perturbation (Veach 1997, sec. 11.4.3): for a path E S* D S+ ... that the
// lens perturbation cannot handle (x_{s+1} is specular, so x_s cannot be reconnected), perturb
// the raster position as the lens perturbation does, then at each non-Dirac vertex whose next
// vertex is Dirac turn the outgoing direction by a log-uniform angle about the current path's
// direction and retrace that specular chain too, until a vertex that can be connected to the
// rest of the path (or the light, hit again). All perturbation densities are symmetric, so
//   T(y->x) / T(x->y) = p(x_1 .. x_c) / p(y_1 .. y_c)
// with the retraced vertices' densities (path_edits.h: retracedEyeDensity).
#pragma once

#include "mcmc/mutation.h"
#include "mcmc/perturbation_sizes.h"

namespace partita {

class Camera;
class RenderScene;

class MultiChainPerturbation : public Mutation {
  public:
    /// `pixels`: the raster offset's range; `angles`: the deflection's range in radians.
    MultiChainPerturbation(const RenderScene& scene, const Camera& camera, PerturbationRange pixels,
                           PerturbationRange angles)
        : scene_(scene), camera_(camera), pixels_(pixels), angles_(angles) {}

    std::string name() const override { return "multi_chain"; }
    bool appliesTo(const MarkovPath& x) const override;
    bool propose(const MarkovPath& x, Rng& rng, MarkovPath& y, double& reverseOverForward,
                 uint64_t& rays) override;

  private:
    const RenderScene& scene_;
    const Camera& camera_;
    PerturbationRange pixels_, angles_;
};

}  // namespace partita
