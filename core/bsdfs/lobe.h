// Shared types for BSDF lobes. A lobe works in the local shading frame: z is the shading normal,
// wo and wi point away from the surface. Every lobe provides (sample's wi in the local frame)
//   Rgb eval(Vec3f wo, Vec3f wi, TransportMode) const;
//   float pdf(Vec3f wo, Vec3f wi) const;
//   std::optional<BsdfSample> sample(Vec3f wo, float uc, Vec2f u, TransportMode) const;
//   bool isDelta() const;
//   Rgb albedo() const;
#pragma once

#include "math/vec.h"

namespace partita {

enum class TransportMode { Radiance, Importance };

struct BsdfSample {
    Rgb f{0.0f};    // BSDF value (Dirac: weight / |cos|)
    Vec3f wi;       // sampled direction (local frame inside lobes, world frame from Bsdf)
    float pdf = 0;  // solid-angle density (Dirac: discrete branch probability)
    bool isDelta = false;
    bool isTransmission = false;
    float eta = 1;  // relative index of refraction crossed when transmitted, else 1
};

}  // namespace partita
