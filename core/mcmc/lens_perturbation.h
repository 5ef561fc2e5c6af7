// Veach's lens perturbation (Veach 1997, sec. 11.4.3): for a path E S* D ... whose first
// non-Dirac vertex x_s can be connected to x_{s+1}, move the raster position by a log-uniform
// offset (perturbation_sizes.h), retrace the camera ray through the same specular chain (same
// branches) to a new x_s, and reconnect it to x_{s+1}; a light seen through the chain (x_s the
// light itself) must be hit again. The offset's density is symmetric, so
//   T(y->x) / T(x->y) = p(x_1 .. x_s | raster) / p(y_1 .. y_s | raster),
// the densities of the retraced vertices (path_edits.h: retracedEyeDensity).
#pragma once

#include <vector>

#include "mcmc/mutation.h"
#include "mcmc/perturbation_sizes.h"

namespace partita {

class Camera;
class RenderScene;

/// The perturbed camera prefix y_0 .. y_s of the lens and multi-chain perturbations: the raster
/// position moved by an offset of size in `pixels`, the camera ray retraced through x's specular
/// chain. Returns s (the first non-Dirac vertex), or -1 when the new prefix has another
/// structure or leaves the image.
int retraceLensPrefix(const RenderScene& scene, const Camera& camera, const MarkovPath& x,
                      const PerturbationRange& pixels, Rng& rng, std::vector<PathVertex>& y,
                      uint64_t& rays);

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
