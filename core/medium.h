// Absorption inside closed meshes whose material has KHR_materials_volume (Beer-Lambert, no
// scattering): the coefficient from the material, and the transmittance along a segment.
#pragma once

#include <cmath>

#include "material.h"
#include "math/vec.h"

namespace partita {

/// Absorption coefficient of a KHR_materials_volume: attenuationColor is the colour white light
/// has after travelling attenuationDistance, so sigma_a = -ln(c) / d. Black without a volume.
inline Rgb absorptionOf(const Material& m) {
    if (!m.hasVolume || !std::isfinite(m.attenuationDistance) || m.attenuationDistance <= 0)
        return Rgb(0.0f);
    Rgb s;
    for (int k = 0; k < 3; ++k)
        s[k] = -std::log(std::max(m.attenuationColor[k], 1e-6f)) / m.attenuationDistance;
    return s;
}

/// exp(-sigma_a d) per channel.
inline Rgb beerLambert(Rgb sigmaA, float distance) {
    if (isBlack(sigmaA)) return Rgb(1.0f);
    return {std::exp(-sigmaA.x * distance), std::exp(-sigmaA.y * distance),
            std::exp(-sigmaA.z * distance)};
}

}  // namespace partita
