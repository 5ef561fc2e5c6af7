// Error of a render against a reference, layer by layer, and the error of a reference estimated
// from two independent halves. Pure arithmetic on Images (the quality harness, partita-eval,
// reads and writes the files).
//
// Both metrics are per channel: every pixel's R, G and B count as three values.
//   RMSE   = sqrt(mean over values of (x - r)^2)
//   relMSE = mean over values of (x - r)^2 / (r^2 + 1e-2)
// relMSE weighs an error by the brightness of the reference there (the 1e-2 keeps black pixels
// from dividing by zero); it is the relative MSE of pbrt's imgtool and of the MCMC literature.
// Sums run in double.
#pragma once

#include <string>
#include <vector>

#include "image.h"

namespace partita {

/// The name of the combined image in a LayerError list (as the Python client calls it).
inline constexpr const char* kCombinedLayerName = "combined";
inline constexpr double kRelMseEpsilon = 1e-2;

/// Both images must have one size (std::invalid_argument naming both otherwise); 0 for no pixels.
double rmse(const Image& x, const Image& ref);
double relMse(const Image& x, const Image& ref);
/// Sum over pixels of (luminance of a - luminance of b)^2, in pixel order (deterministic): the
/// spread of two independent estimates of one image (the pilots' variances). Same-size images.
double luminanceSquaredDifference(const Image& a, const Image& b);

struct LayerError {
    std::string layer;
    double rmse = 0, relMse = 0;
};

/// "combined" first, then every layer that both images have, in the reference's order, except
/// "other" (Film::kOtherLayer): what it holds depends on which types each film kept.
/// std::invalid_argument when the sizes differ.
std::vector<LayerError> compareLayers(const LayeredImage& x, const LayeredImage& ref);

/// When a film had more types than it keeps, it merges the rest into "other", and two renders
/// keep different types. Then every layer that only one of `a` and `b` has is added into that
/// image's "other" (created if needed, last) and removed, so that both hold the same types and
/// each type is in the same layer of both. Without "other" in either, nothing changes: a layer
/// that one render lacks is then a type it never sampled, black.
void foldUnsharedLayers(LayeredImage& a, LayeredImage& b);

/// The pixel-wise mean of two renders of one budget, layer by layer: the layers of `a` in its
/// order, then those only `b` has; a layer missing from one image counts as black there.
/// `a` is taken by value so that a caller can move it in and the mean reuses its memory.
LayeredImage meanOfTwo(LayeredImage a, const LayeredImage& b);

/// The error of meanOfTwo(a, b) against its expectation, for two independent renders a and b of
/// equal budget (same variance s^2 per value): E[(a - b)^2] = 2 s^2 and the mean has variance
/// s^2 / 2, so its RMSE is rms(a - b) / 2, and its relMSE mean((a - b)^2 / 4 / (m^2 + 1e-2))
/// with m the mean image standing in for the unknown expectation. Per layer of meanOfTwo's list,
/// "combined" first.
std::vector<LayerError> halfSplitError(const LayeredImage& a, const LayeredImage& b);

}  // namespace partita
