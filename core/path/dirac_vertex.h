// Dirac (specular) vertices in ratios of densities: what the MCMC methods need that BDPT's MIS
// does not.
//
// f(x) and the density of any strategy that samples x carry the same Dirac delta at each
// specular vertex, so f / p is finite although neither is. MIS only needs ratios of densities of
// one path, where the delta cancels and is stored as 0 (mis.h); a Metropolis acceptance
// f(y) T(y->x) / (f(x) T(x->y)) needs f / T of each path separately, where a delta cancels only
// if f and T agree on which delta they hold. The convention here: every delta is written in
// the solid angle of the direction towards the light, delta(w_L - R(w_E)), at the vertex. Then
// - f holds the branch's coefficient: the radiance-mode BSDF sample's f (its weight / |cos|);
// - a vertex generated from the camera side through it holds the branch's probability (the
//   walk picks reflection or refraction at random), or 1 when the branch is followed on purpose
//   (a perturbation retracing the same specular chain);
// - a vertex generated from the light side holds the probability times J = dw_L / dw_E, because
//   that side samples delta(w_E - R^-1(w_L)) = J delta(w_L - R(w_E)). J is 1 for a reflection
//   and eta_E^2 cos_E / (eta_L^2 cos_L) for a refraction (conservation of etendue).
#pragma once

#include "math/vec.h"
#include "path/path_vertex.h"

namespace partita {

struct DiracBranch {
    bool valid = false;
    Rgb f{0.0f};                 // radiance-mode coefficient / |cos(w_L)| (bsdf.h's Dirac f)
    float probabilityEye = 0;    // of picking this branch when sampling from the camera side
    float probabilityLight = 0;  // ... from the light side
    float jacobian = 1;          // J = dw_L / dw_E
};

/// The branch of the Dirac vertex v that links the directions towards the eye side and the
/// light side (reflection when both lie on the same side of the geometric normal, else
/// refraction); invalid when v's lobe has no such branch (total internal reflection, a mirror
/// seen from behind).
DiracBranch diracBranch(const PathVertex& v, Vec3f toEye, Vec3f toLight);

}  // namespace partita
