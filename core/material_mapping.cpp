#include "material_mapping.h"

#include <cmath>

#include "math/frame.h"

namespace partita {

namespace {

// The texel a material slot sees at this point; nullopt when the slot has no (valid) texture.
std::optional<Rgba> lookup(const TextureRef& ref, const std::vector<Texture>& textures,
                           const std::array<Vec2f, 2>& uv, const bool hasUv[2]) {
    if (!ref.valid() || size_t(ref.texture) >= textures.size()) return std::nullopt;
    int set = (ref.texCoord == 1 && hasUv[1]) ? 1 : 0;
    return textures[size_t(ref.texture)].lookup(ref.transformUv(uv[size_t(set)]));
}

float clamp01(float v) { return std::isfinite(v) ? clamp(v, 0.0f, 1.0f) : 0.0f; }
Rgb clamp01(Rgb c) { return {clamp01(c.x), clamp01(c.y), clamp01(c.z)}; }

}  // namespace

Bsdf makeBsdf(const Material& m, const std::vector<Texture>& textures, const SurfacePoint& sp) {
    Rgb baseColor = m.baseColor;
    float metallic = m.metallic, roughness = m.roughness, transmission = m.transmission;
    if (auto t = lookup(m.baseColorTexture, textures, sp.uv, sp.hasUv)) baseColor *= t->rgb;
    if (auto t = lookup(m.metallicRoughnessTexture, textures, sp.uv, sp.hasUv)) {
        roughness *= t->rgb.y;
        metallic *= t->rgb.z;
    }
    if (auto t = lookup(m.transmissionTexture, textures, sp.uv, sp.hasUv)) transmission *= t->rgb.x;
    baseColor = clamp01(baseColor);
    metallic = clamp01(metallic);
    roughness = clamp01(roughness);
    transmission = clamp01(transmission);
    float alpha = roughness * roughness;

    Frame frame = Frame::fromNormal(sp.ns);
    auto make = [&](BsdfLobe lobe) { return Bsdf(frame, sp.ng, lobe); };

    // Rule numbers refer to the comment block in material_mapping.h.
    if ((1 - metallic) * transmission >= 0.5f) {  // 1
        float ior = std::isfinite(m.ior) && m.ior > 0 ? m.ior : 1.5f;
        if (std::abs(ior - 1) < 1e-3f) return make(SmoothDielectricLobe{1.0f, baseColor});
        if (roughness < kSmooth) return make(SmoothDielectricLobe{ior, baseColor});
        return make(DielectricLobe{ior, alpha, baseColor});
    }
    if (metallic == 0) return make(LambertLobe{baseColor});  // 2
    if (roughness < kSmooth) {                               // 3
        if (metallic >= 0.5f) return make(MirrorLobe{baseColor * metallic});
        return make(LambertLobe{baseColor * (1 - metallic)});
    }
    if (metallic == 1) return make(ConductorLobe{baseColor, alpha});  // 4
    return make(DiffuseConductorMixLobe{LambertLobe{baseColor}, ConductorLobe{baseColor, alpha},
                                        metallic});  // 5
}

Rgb evalEmission(const Material& m, const std::vector<Texture>& textures,
                 const std::array<Vec2f, 2>& uv) {
    Rgb e = m.emissionScale();
    if (isBlack(e)) return e;
    // The caller passes (0, 0) for UV sets the mesh lacks; there is no hasUv here, so a texture
    // naming an absent set 1 reads uv[1] as given.
    const bool hasUv[2] = {true, true};
    if (auto t = lookup(m.emissiveTexture, textures, uv, hasUv)) e *= t->rgb;
    return e;
}

}  // namespace partita
