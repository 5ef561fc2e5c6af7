// The image-space approximation of the guided perturbation for one partition (paper Sec. 5.1,
// Eq. 15 and 17): S'(q), the approximate contribution of the camera prefix through pixel q
// connected to the fixed vertex x_{s+1}, from the G-buffer (gbuffer.h) and V', the visibility
// approximation thresholded from the partition's denoised pre-pass image D_i (denoise.h).
//
// Eq. 15, with our measure: S'(q) = G_q rho_q / pi * cos(theta_q) cos(theta') / d^2 * V'_q,
// G_q the G-buffer's camera term (the specular chain's throughput: our proposal is a density
// on the image plane, where the camera's importance is constant), rho_q the albedo, theta_q the
// angle at the G-buffer's normal and theta' the angle at x_{s+1}'s normal towards the other, d
// their distance (the paper's ||.||_2 in the geometry term is the squared distance). A fixed
// vertex without a surface (a point light) has no cos(theta'); one at infinity (the
// environment, a directional light) has neither cos(theta') nor d^2: its stand-in point only
// gives the direction.
//
// Eq. 17: V'_q = 1 if D_i(q) > epsilon, else epsilon. D_i is taken relative to its mean over
// the pixels where it is positive (relativeToMean), so that epsilon does not depend on the
// partition's brightness (the paper leaves D's scale open). Only the threshold is kept, one bit
// a pixel (support_mask.h).
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include "guide/gbuffer.h"
#include "guide/guided_choice.h"
#include "guide/offsets.h"
#include "guide/support_mask.h"
#include "path/path_vertex.h"

namespace partita {

/// D divided by its mean over the pixels where it is positive (all zero stays all zero): the
/// scale on which Eq. 17's epsilon is read.
std::vector<float> relativeToMean(const std::vector<float>& d);

class ImageGuide {
  public:
    /// The guide of partition `partition`: its bits D_i > epsilon in `masks` (made from
    /// relativeToMean of each D_i). `gbuffer` and `masks` must outlive the guide.
    ImageGuide(const GBuffer& gbuffer, const SupportMasks& masks, size_t partition)
        : gbuffer_(&gbuffer), masks_(&masks), partition_(partition) {}

    int width() const { return gbuffer_->width(); }
    int height() const { return gbuffer_->height(); }

    /// V'_q (paper Eq. 17).
    float vPrime(int x, int y) const {
        return masks_->above(partition_, x, y) ? 1.0f : masks_->epsilon();
    }
    /// S'(q) for the fixed vertex `anchor` (x_{s+1}); 0 where the G-buffer has no valid texel.
    /// Inline: the guided move evaluates it |Y'| times for each new pixel (candidates below).
    /// paper Eq. 15
    float sPrime(int x, int y, const PathVertex& anchor) const {
        const GBufferTexel& texel = gbuffer_->at(x, y);
        if (!texel.valid) return 0;
        Vec3f d = anchor.p - texel.position;
        float dist2 = lengthSquared(d);
        if (!(dist2 > 0)) return 0;
        Vec3f w = d / std::sqrt(dist2);
        float geometry = absDot(texel.normal, w);
        if (!anchor.atInfinity) geometry *= geometricCos(anchor, w) / dist2;
        float s = texel.cameraTerm * texel.albedo * float(M_1_PI) * geometry * vPrime(x, y);
        return std::isfinite(s) ? s : 0.0f;
    }
    /// The candidates Y'(p) around pixel (px, py) (guided_choice.h): S'(p + delta_k) for every
    /// k, 0 off the image, and their sum (in k's order). With AVX2, eight candidates at a time
    /// (image_guide_candidates.cpp): the same formula as sPrime's arranged with one division,
    /// so equal to it within a few ulps; every lane computes alike, so a pixel reached by
    /// several offsets gets the same weight from each (Eq. 16's ratio needs that exactly).
    void candidates(const OffsetLanes& offsets, int px, int py, const PathVertex& anchor,
                    CandidateWeights& out) const;

    /// The fraction of pixels with V' = 1.
    double supportFraction() const;

  private:
    const GBuffer* gbuffer_;
    const SupportMasks* masks_;
    size_t partition_;
};

}  // namespace partita
