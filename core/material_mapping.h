// How a glTF material becomes a BSDF at a surface point, and what it emits.
//
// Inputs (each factor x texture, clamped to [0, 1]; textures are looked up at
// ref.transformUv(uv[ref.texCoord]), falling back to TEXCOORD_0 when the named set is absent):
//   baseColor    = baseColorFactor.rgb x baseColorTexture.rgb (alpha / alphaMode are not used)
//   metallic     = metallicFactor  x metallicRoughnessTexture.B
//   roughness    = roughnessFactor x metallicRoughnessTexture.G
//   transmission = transmissionFactor x transmissionTexture.R   (KHR_materials_transmission)
//   ior          = KHR_materials_ior (default 1.5)
//
// kSmooth = 0.02 (roughness). Below it a surface becomes a Dirac lobe (S vertex). GGX with
// alpha = roughness^2 = 4e-4 has a reflected lobe about 2 alpha ~ 1e-3 rad wide, well under the
// angle one pixel subtends in the shipped scenes (~2.5e-3 rad at 320 px across a 0.8 rad field of
// view), so the mirror looks the same; and a near-Dirac D vertex is the worst case for next-event
// estimation, BDPT connections and MCMC perturbations, which would all see it as diffuse yet
// almost never hit its lobe. Exporters also write "perfectly smooth" as 0 or a small epsilon
// (0.01 is common), which this threshold catches. Rough lobes clamp alpha to kMinAlpha (1e-3)
// for float robustness, so roughness in [0.02, 0.032) renders as alpha = 1e-3.
//
// Rules, first match wins. One BSDF never mixes a Dirac lobe with a non-Dirac one, so a vertex's
// Heckbert type (S or D) is unambiguous, which the partitioning by path type relies on.
//  1. Transmissive: (1 - metallic) x transmission >= 0.5, the weight glTF gives to the
//     transmission BTDF (metals do not transmit).
//     - |ior - 1| < 1e-3: SmoothDielectric(eta = 1, tint = baseColor) at any roughness: an
//       index-matched interface passes light straight through, a Dirac event.
//     - roughness < kSmooth: SmoothDielectric(eta = ior, tint = baseColor)      (S)
//     - else Dielectric(eta = ior, alpha = roughness^2, tint = baseColor)       (D)
//     The base colour tints transmission only, as in glTF; the opaque (1 - transmission) part
//     and any metallic share are dropped: a binary choice keeps the vertex type unambiguous.
//  2. metallic == 0: Lambert(baseColor) at any roughness. Rough dielectric base: glTF's 4%
//     specular coat is not modelled (it would need a layered D lobe, and on a smooth dielectric
//     it would be a Dirac+diffuse mix, which rule "never mix" forbids).
//  3. roughness < kSmooth (the Dirac regime), the larger of the two glTF weights wins and keeps
//     its own weight (the other part is dropped rather than renormalised, so the result never
//     reflects more than glTF's model, and a filtered metal/dielectric texture edge darkens
//     smoothly instead of brightening):
//     - metallic >= 0.5: Mirror(tint = metallic x baseColor; Schlick Fresnel, F0 = tint) (S)
//     - else Lambert(reflectance = (1 - metallic) x baseColor)                       (D)
//  4. metallic == 1: Conductor(F0 = baseColor, alpha = roughness^2)               (D)
//  5. else DiffuseConductorMix(Lambert(baseColor), Conductor(F0 = baseColor, alpha =
//     roughness^2), weight metallic): glTF's mix(dielectric, metal, metallic) with the dielectric
//     reduced to Lambert as in rule 2.                                             (D)
//
// Surfaces are two-sided for opaque lobes (Bsdf mirrors the frame when wo is behind ng);
// glTF's doubleSided (a rasteriser's culling switch) does not change the BSDF.
//
// Emission = emissiveFactor x emissiveTexture.rgb x KHR_materials_emissive_strength.
#pragma once

#include <array>
#include <vector>

#include "bsdf.h"
#include "material.h"
#include "math/vec.h"
#include "texture.h"

namespace partita {

/// Roughness below which a material maps to a Dirac lobe (see above).
constexpr float kSmooth = 0.02f;

/// What makeBsdf needs to know about the point. `ng` (unit geometric normal, from the triangle's
/// counter-clockwise winding: glTF's front face) and `ns` (unit shading normal, flipped into
/// ng's hemisphere) face the surface's FRONT side, independent of where the ray came from. For
/// transmissive materials the front is the outside of the medium; opaque lobes are two-sided.
struct SurfacePoint {
    Vec3f ng{0, 0, 1};
    Vec3f ns{0, 0, 1};
    std::array<Vec2f, 2> uv{};  // TEXCOORD_0, TEXCOORD_1
    bool hasUv[2] = {false, false};
};

/// The BSDF of material `m` at `sp`; `textures` is SceneData::textures.
Bsdf makeBsdf(const Material& m, const std::vector<Texture>& textures, const SurfacePoint& sp);

/// Emitted radiance: emissiveFactor x emissiveTexture.rgb x emissiveStrength.
Rgb evalEmission(const Material& m, const std::vector<Texture>& textures,
                 const std::array<Vec2f, 2>& uv);

}  // namespace partita
