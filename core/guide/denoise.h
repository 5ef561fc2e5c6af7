// The per-partition denoiser of the guided image perturbation (paper Sec. 5.1.1, DESIGN.md
// "Denoising"): each partition's pre-pass image (partition/partition_images.h) is smoothed into
// D_i, whose threshold gives the visibility approximation V' of Eq. 17.
//
// Why an edge-avoiding a-trous wavelet filter (Dammertz et al. 2010, "Edge-avoiding A-Trous
// wavelet transform for fast global illumination filtering"), guided by the G-buffer:
// - it is edge-avoiding: a tap's weight falls with the difference of normals, albedos and the
//   tap's distance from the pixel's tangent plane, and is zero on another surface, another
//   specular chain length or an invalid texel, so a partition's light does not bleed across
//   objects and the support of a partition (where its paths land) is preserved;
// - its cost is O(levels) per pixel, independent of the radius it reaches: level l spaces the
//   taps of a fixed 3x3 kernel 2^l pixels apart, so 5 levels reach 31 pixels with 45 taps,
//   which the pre-pass's ~0.1 sample a pixel (at 1280x720) needs;
// - it needs only the guides we have (OIDN is not available; no colour variance estimate is
//   needed, unlike SVGF): since the weights depend on the G-buffer alone, each tap's weight is
//   computed once and applied to every partition's channel at once (K + 1 = 11 partitions at
//   1280x720 cost about one more channel pass each, not one more filter);
// - its output is only thresholded (Eq. 17), so what matters is where it is zero or small,
//   not its fine detail; Metropolis noise is never denoised (DESIGN.md: the pre-pass only).
// The weights are normalised per pixel and applied to differences, out(p) = in(p) +
// sum_q w_q (in(q) - in(p)) / sum_q w_q, so a constant stays exactly constant and zero stays
// exactly zero wherever every tap with weight reads that constant or zero.
#pragma once

#include <vector>

#include "guide/gbuffer.h"

namespace partita {

class ThreadPool;

/// The edge stops' widths (a sigma <= 0 switches its term off). The position term is scale-free:
/// the sine of the angle between the tap's offset and p's tangent plane, so it stops at creases
/// and depth steps on one mesh whatever the scene's units. Defaults set by reasoning (a 90 degree
/// crease or an albedo step of 0.3 weighs ~e^-9 or less), not by a sweep; the figures in
/// docs/guide-buffers.md are with these.
struct DenoiseSettings {
    int levels = 5;              // a-trous levels: taps 1, 2, 4, ... 2^(levels-1) pixels apart
    float normalSigma = 0.3f;    // weight exp(-|n_p - n_q|^2 / sigma^2)
    float albedoSigma = 0.1f;    // weight exp(-(rho_p - rho_q)^2 / sigma^2), luminance albedos
    float positionSigma = 0.1f;  // weight exp(-(n_p . (x_q - x_p) / |x_q - x_p|)^2 / sigma^2)
};

/// Denoised copies of `images` (each width*height luminance, e.g. partitionPrepassImages), one
/// per input, same order. Taps on another surface id, with another number of specular vertices
/// in front of them, or on an invalid texel get weight 0 (support is preserved: light does not
/// bleed across objects); weights are normalised per pixel, so a constant image stays exactly
/// constant on each surface; a pixel whose valid neighbourhood is empty (an invalid texel)
/// keeps its input. Parallel on `pool` (may be nullptr), deterministic: the same output for any
/// thread count. std::invalid_argument when an image's size is not the G-buffer's.
std::vector<std::vector<float>> denoisePartitions(const GBuffer& gbuffer,
                                                  const std::vector<std::vector<float>>& images,
                                                  const DenoiseSettings& settings,
                                                  ThreadPool* pool);

}  // namespace partita
