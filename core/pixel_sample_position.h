// Where a pixel's samples fall inside it (pt, bdpt and the per-pixel partitions): stratified
// over the pixel's sample indices instead of independent. The light seen directly, directly or
// through glass, has its variance at edges inside a pixel; a stratified position makes that
// error fall as about N^-1.5 instead of N^-1 (measured on cornell-glass: docs/pixel-samples.md).
//
// Sample s of a pixel takes point s / 2 of a scrambled (0, 2)-sequence of its own parity: the
// even and the odd sample indices follow two independently scrambled sequences. So the two
// halves the render's own error estimate compares (half_split_error.h: the odd indices against
// the rest) are independent and alike, as with independent samples; one sequence over all
// indices would put every even index in one half of the pixel and every odd one in the other.
// Every point is uniform over the pixel, so every estimator stays unbiased; the position
// depends only on (seed, pixel, sample index), so images still depend on neither threads,
// passes nor shards.
#pragma once

#include <cstdint>

#include "math/vec.h"

namespace partita {

/// Point `n` of the first two dimensions of the Sobol sequence, a (0, 2)-sequence in base 2
/// (van der Corput and Sobol's second dimension), each XOR-scrambled by a random 32-bit value:
/// every point is uniform over the unit square, and the first 2^k points fall one in each of
/// 2^k equal elementary intervals (Kollig & Keller 2002, "Efficient multidimensional
/// sampling"), whatever the count turns out to be.
Vec2f scrambledSobol02(uint32_t n, uint32_t scrambleX, uint32_t scrambleY);

/// u in [0, 1)^2 of sample `sampleIndex` of pixel `pixelIndex` under `seed` (above); the
/// raster position is filteredRasterPosition(x, y, u) (integrators/pt/pt_integrator.h).
Vec2f pixelSamplePosition(uint64_t seed, uint64_t pixelIndex, uint64_t sampleIndex);

}  // namespace partita
