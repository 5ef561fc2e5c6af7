// Veach's caustic perturbation (Veach 1997, sec. 11.4.3): for a path E D S+ (D|L) ... (a
// caustic seen on a diffuse surface), turn the direction leaving x_a (the first non-Dirac vertex
// after the specular chain, counted from the eye) towards x_{a-1} by a log-uniform angle,
// retrace the chain from the light side with the same branches to a new x_1, and connect x_1 to
// the camera. The angle's density is symmetric, so
//   T(y->x) / T(x->y) = p(x_{a-1} .. x_1) / p(y_{a-1} .. y_1)
// with the retraced vertices' densities from the light side (path_edits.h:
// retracedLightDensity, which carries the refraction Jacobians of dirac_vertex.h).
#pragma once

#include "mcmc/mutation.h"
#include "mcmc/perturbation_sizes.h"

namespace partita {

class Camera;
class RenderScene;

class CausticPerturbation : public Mutation {
  public:
    /// `angles`: the deflection's smallest and largest angle in radians.
    CausticPerturbation(const RenderScene& scene, const Camera& camera, PerturbationRange angles)
        : scene_(scene), camera_(camera), angles_(angles) {}

    std::string name() const override { return "caustic"; }
    bool appliesTo(const MarkovPath& x) const override;
    bool propose(const MarkovPath& x, Rng& rng, MarkovPath& y, double& reverseOverForward,
                 uint64_t& rays) override;

  private:
    const RenderScene& scene_;
    const Camera& camera_;
    PerturbationRange angles_;
};

}  // namespace partita
