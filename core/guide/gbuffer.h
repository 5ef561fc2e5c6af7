// The G-buffer of the guided image perturbation (paper Sec. 5.1 and 5.1.1): per pixel, the first
// non-specular vertex x_s seen through the pixel centre, with what Eq. 15's approximation S' of
// a prefix's contribution needs there (position, normal, albedo rho_j, the camera term G_j) and
// what the per-partition denoiser uses as edge stops (denoise.h: normal, albedo, position, the
// surface and the length of the specular chain in front of it).
//
// G_j, the camera term. The guided proposal is a density on the image plane (DESIGN.md, "Guided
// image perturbation", step 4), so the paper's G(x0 <-> x1) is needed together with the
// Jacobian from the image plane to x1: G(x0 <-> x1) dA(x1) = cos(theta_0) dw, and a unit of
// image area at distance 1 spans dw = cos^3(theta_0) dA_image, so the pinhole's importance
// We = 1 / (A cos^4(theta_0)) (camera.h) times both is 1 / A per unit image area: the same for
// every pixel. What does vary from pixel to pixel is the throughput of the specular chain
// x1 .. x_{s-1} in front of x_s, the coefficients of the Dirac branches followed (Fresnel
// reflectance or transmittance, glass tint, the mirror's Fresnel; the radiance-mode 1 / eta^2
// of entering a denser medium cancels on leaving it). So cameraTerm is the luminance of the
// product of the followed branches' weights (their f |cos|, path/dirac_vertex.h), 1 for a
// surface seen directly: a relative G_j, the constant 1 / A dropping out of S'(q) / sum S'.
//
// Why a pass of its own. The paper fills the G-buffer from the pre-pass's paths; ours draws
// raster positions uniformly over the image (mcmc/bootstrap.h), ~0.1 sample a pixel at
// 1280x720 with the default 10^5 samples, so most pixels would have none. buildGBuffer traces
// one deterministic camera ray through each pixel centre instead (1280x720: ~0.9 M rays plus
// the specular chains, well under the pre-pass's cost).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "algorithm.h"
#include "math/vec.h"

namespace partita {

struct GBufferTexel {
    Vec3f position;        // of the first non-specular vertex seen through the pixel centre
    Vec3f normal;          // its unit shading normal, facing the incoming camera ray
    float albedo = 0;      // luminance of Bsdf::albedo() there
    float cameraTerm = 0;  // G_j: the luminance of the followed Dirac branches' weights (above)
    uint32_t surface = 0;  // mesh index of that vertex (edge stop for the denoiser)
    uint8_t specularVertices = 0;  // Dirac vertices before it on the camera side (at most 255)
    /// false: the ray left the scene, hit a light/emitter only (the first non-specular vertex is
    /// on an area light), or ended in a Dirac chain (no branch to follow, longer than maxDepth).
    bool valid = false;
};

class GBuffer {
  public:
    GBuffer() = default;
    GBuffer(int width, int height);

    int width() const { return width_; }
    int height() const { return height_; }
    /// x in [0, width), y in [0, height), row 0 at the top as in Image.
    const GBufferTexel& at(int x, int y) const { return texels_[size_t(y) * width_ + x]; }
    GBufferTexel& at(int x, int y) { return texels_[size_t(y) * width_ + x]; }
    /// The texels, row-major (index y * width + x).
    const std::vector<GBufferTexel>& texels() const { return texels_; }
    /// Memory held by the texels (40 B a pixel).
    size_t bytes() const { return texels_.size() * sizeof(GBufferTexel); }

  private:
    int width_ = 0, height_ = 0;
    std::vector<GBufferTexel> texels_;
};

/// One camera ray through each pixel centre (raster x + 0.5, y + 0.5), followed through Dirac
/// vertices along the more probable branch (reflection or refraction; a mirror reflects) up to
/// maxDepth scattering vertices, parallel over rows on `pool`, deterministic (no randomness).
/// Cancellable via ctx (throws RenderCancelled). Uses ctx.scene, ctx.camera,
/// ctx.settings.maxDepth; the size is the camera's (ctx.settings' width and height).
GBuffer buildGBuffer(const RenderContext& ctx);
}  // namespace partita
