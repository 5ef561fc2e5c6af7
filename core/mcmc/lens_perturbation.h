// Veach's lens perturbation (Veach 1997, sec. 11.4.3): for a path E S* D ... whose first
// non-Dirac vertex x_s can be connected to x_{s+1}, move the raster position by a log-uniform
// offset (perturbation_sizes.h), retrace the camera ray through the same specular chain (same
// branches) to a new x_s, and reconnect it to x_{s+1}; a light seen through the chain (x_s the
// light itself) must be hit again. The offset's density is symmetric, so
//   T(y->x) / T(x->y) = p(x_1 .. x_s | raster) / p(y_1 .. y_s | raster),
// the densities of the retraced vertices (path_edits.h: retracedEyeDensity).
#pragma once

#include "mcmc/mutation.h"
#include "mcmc/perturbation_sizes.h"

namespace partita {

class Camera;
class RenderScene;

class LensPerturbation : public Mutation {
  public:
    /// `pixels`: the offset's smallest and largest size in pixels.
    LensPerturbation(const RenderScene& scene, const Camera& camera, PerturbationRange pixels)
        : scene_(scene), camera_(camera), pixels_(pixels) {}

    std::string name() const override { return "lens"; }
    bool appliesTo(const MarkovPath& x) const override;
    bool propose(const MarkovPath& x, Rng& rng, MarkovPath& y, double& reverseOverForward,
                 uint64_t& rays) override;

  private:
    const RenderScene& scene_;
    const Camera& camera_;
    PerturbationRange pixels_;
};

}  // namespace partita
