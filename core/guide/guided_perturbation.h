// The guided image perturbation (paper Sec. 5.1, Eq. 15-18; DESIGN.md "Guided image
// perturbation"): the lens perturbation's move on the image plane, with the new pixel drawn
// from the candidates Y'(p) around the current pixel p in proportion to S' (image_guide.h)
// instead of a fixed offset density.
//
// For a path E S* D ... with x_s its first non-Dirac vertex and the suffix x_{s+1} .. x_M kept:
// candidates q = p + delta (offsets.h), one chosen with probability P(q | Y'(p))
// (guided_choice.h), a raster position uniform inside q, the camera ray retraced through the
// same specular branches to a new x'_s, reconnected to x_{s+1}. In the area measure of the
// vertices (mutation.h), with T on the image plane times the Jacobian of the retrace:
//   T(y->x) / T(x->y) = [P(p | Y'(q)) / P(q | Y'(p))] * p(x_1..x_s | raster) / p(y_1..y_s |
//   raster),
// the second factor the lens perturbation's (path_edits.h retracedEyeDensity). With f in that
// measure, min(1, f*(y) T(y->x) / (f*(x) T(x->y))) is paper Eq. 16.
//
// It replaces the lens perturbation: it applies where the lens perturbation does, and a path
// whose first non-Dirac vertex is its light (E S* L: no fixed vertex to connect to) falls back
// to the lens perturbation. So does, unless `throughSpecular`, a path whose camera ray meets a
// specular surface before x_s (E S+ D ...): the G-buffer follows the more probable Dirac branch
// (gbuffer.h), so S' describes another surface than x_s wherever the path takes the other branch
// (a reflection in glass), and the chains' pilot measured the guided move 1.2-2.9x worse per
// mutation than the lens perturbation on such types (docs/partition-estimators.md, "Where the
// guided move pays"). Both moves keep the path's structure (s, the branches followed), so each
// choice is the same from either end of a move: the kernel is a mixture over classes the moves
// never leave, each class with one exact kernel. A current raster position outside the image's
// pixels (the importance support reaches half a pixel beyond them) cannot be proposed by the guided
// move, so it is never left by it either: a rejection.
//
// The candidate sums are the costly part (|Y'| G-buffer reads each): the sums of the last two
// pixels are kept with their anchor, so a rejected proposal (the chain stays) or an accepted one
// (the chain moves to the pixel whose sum was just computed) reuses one of them. They are pure
// functions of (pixel, anchor), so reuse changes no result.
#pragma once

#include <memory>
#include <vector>

#include "guide/guided_choice.h"
#include "guide/image_guide.h"
#include "mcmc/lens_perturbation.h"

namespace partita {

class GuidedPerturbation : public Mutation {
  public:
    /// `guide` (the chain's partition) and `delta` outlive the mutation; `lensPixels` are the
    /// fallback lens perturbation's offset sizes; `throughSpecular`: the guided move also for
    /// paths E S+ D ... (the paper's), else the lens perturbation for them (above).
    GuidedPerturbation(const RenderScene& scene, const Camera& camera, const ImageGuide& guide,
                       const std::vector<PixelOffset>& delta, PerturbationRange lensPixels,
                       bool throughSpecular);

    std::string name() const override { return "guided"; }
    bool appliesTo(const MarkovPath& x) const override { return lens_.appliesTo(x); }
    bool propose(const MarkovPath& x, Rng& rng, MarkovPath& y, double& reverseOverForward,
                 uint64_t& rays) override;

    /// Candidate sums computed and reused (a cache hit skips |Y'| G-buffer reads).
    uint64_t sumsComputed() const { return computed_; }
    uint64_t sumsReused() const { return reused_; }
    /// sum_{Y'(q)} S' / sum_{Y'(p)} S' of the last guided proposal (a test's negative control
    /// multiplies it back out of the ratio).
    double lastSumRatio() const { return lastSumRatio_; }

  private:
    struct CachedCandidates {
        int x = -1, y = -1;
        Vec3f anchor, anchorNormal;
        CandidateWeights weights;
    };
    /// The candidates Y'(x, y) for `anchor`, from the cache or computed into its older slot.
    const CandidateWeights& candidatesAt(int x, int y, const PathVertex& anchor);

    const RenderScene& scene_;
    const Camera& camera_;
    const ImageGuide& guide_;
    const std::vector<PixelOffset>& delta_;
    OffsetLanes lanes_;          // delta_ for the candidate sums' vector loop
    std::vector<int> opposite_;  // the offset back from p + delta_k to p, for each k
    LensPerturbation lens_;
    bool throughSpecular_;
    CachedCandidates cache_[2];
    int older_ = 0;  // the least recently used slot
    double lastSumRatio_ = 1;
    uint64_t computed_ = 0, reused_ = 0;
};

}  // namespace partita
