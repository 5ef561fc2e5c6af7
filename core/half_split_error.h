// The error of a progressive render estimated from the render itself, without a reference:
// two interleaved halves. The samples are split by index (pt, bdpt: the even sample indices of
// every pixel are half A, the odd ones half B: sample_passes.cpp), so the split, and the
// estimate, depend only on the seed and the budget; each half is an independent estimate of the
// same image, so their difference measures the noise. With n_A and n_B samples per pixel in the
// halves, I_A = S_A / n_A and I_B = S_B / n_B, E[(I_A - I_B)^2] = s^2 (1/n_A + 1/n_B) while the
// full image I = (S_A + S_B) / (n_A + n_B) has variance s^2 / (n_A + n_B), so
//     Var(I) ~ (I_A - I_B)^2 n_A n_B / (n_A + n_B)^2        (unbiased per pixel and channel),
// and the estimated relative RMSE of I is sqrt(mean Var(I)) / mean I over pixels and channels
// (the RMSE against the true image, over the image's mean: what `partita-eval quality` measures
// against a long reference, divided by the reference's mean).
//
// It keeps only the combined sums: the whole's and half A's (two float images), either from
// the film's unscaled combined sums after each run of samples of one half (addRun:
// Film::resolveCombined(1)) or from the film's and a film of the odd indices alone
// (setInterleaved). Only valid for independent samples (pt, bdpt): successive rounds
// of a Markov chain are not.
#pragma once

#include <cstdint>

#include "image.h"

namespace partita {

/// An image's estimated error, summed over its pixel-channels, in parts that add up: the
/// variances of independent parts add, and so do their values. An MCMC image is such a sum
/// (mlt: its chains and its per-pixel direct light; partitioned: its partitions), each part
/// estimated by its own means (chain halves, a pilot's variance, a normalising constant's).
struct ErrorSums {
    double variance = 0;  // sum of the estimated Var(I) of every pixel-channel
    double value = 0;     // sum of I
    double squares = 0;   // sum of I^2: of this part alone (not kept through add)
    double count = 0;     // pixel-channels

    /// A part's image is scaled by an estimated constant c (a normalising constant b, E c = 1
    /// relative to the truth) of relative variance r, independent of the rest of its error:
    /// Var(c I) ~ Var(I) + r I^2, so r times the squares is added.
    void addScaleVariance(double relativeVariance);
    /// Adds an independent part of the same image size.
    void add(const ErrorSums& part);
    /// sqrt(variance / count) / (value / count): the relative RMSE (0 for a black image).
    double relativeRmse() const;
};

/// The error sums of the mean of two independent estimates a and b of one image, weighted
/// n_a : n_b (their samples, or mutations), as in HalfSplitError: Var ~ (a - b)^2 n_a n_b / n^2.
/// Zero sums when either weight is 0.
ErrorSums halvesError(const Image& a, const Image& b, double weightA, double weightB);
/// The error sums of `image` whose pixel-channels' variances sum to `variance` (measured apart:
/// a pilot's per-sample variance over the samples per pixel).
ErrorSums imageErrorSums(const Image& image, double variance);
/// The relative variance of a mean S1 / N of N samples whose values sum to S1 and whose squares
/// sum to S2: Var / mean^2 = S2 / S1^2 - 1 / N (at least 0; infinite without a positive sum). A
/// normalising constant's (b), for ErrorSums::addScaleVariance.
double relativeVarianceOfMean(double sum, double sumSquares, double n);
/// A per-sample variance measured by a pilot (`pilot` over its `pilotSamples` per pixel) and by
/// the render's own samples so far (`own` over `samples`: HalfSplitError::
/// perSampleLuminanceVariance), pooled by their counts; the pilot's alone until the render's
/// own has two samples and a variance. The pilot's few samples miss what is bright and rare
/// (pool: the light's glints in the water, about one hit in four passes over the image;
/// docs/mlt-direct-light.md), the render's own samples see it: mlt's direct light and the
/// partitioned methods' per-pixel phase re-read their share of a budget with this.
double pooledVariance(double pilot, double pilotSamples, double own, double samples);

class HalfSplitError {
  public:
    /// The film's unscaled combined sums after a run of `samples` samples per pixel, all of
    /// half A (`halfA`) or all of half B.
    void addRun(const Image& sums, uint64_t samples, bool halfA);
    /// The halves of samples interleaved by index (replacing any runs): `totalSums`, the film's
    /// unscaled combined sums of sample indices [0, samples), and `oddSums`, those of its odd
    /// indices (half B; half A is the rest).
    void setInterleaved(Image totalSums, const Image& oddSums, uint64_t samples);

    uint64_t samplesA() const { return samplesA_; }
    uint64_t samplesB() const { return samplesB_; }
    /// Both halves hold at least `minimum` samples per pixel.
    bool ready(uint64_t minimum = 1) const { return samplesA_ >= minimum && samplesB_ >= minimum; }
    /// The estimated relative RMSE of the full image (0 when not ready or the image is black).
    double relativeRmse() const;
    /// The full image's error sums (zero sums when not ready).
    ErrorSums errorSums() const;
    /// The per-sample variance of a pixel's estimate in luminance, summed over pixels:
    /// n sum over pixels of lum(I_A - I_B)^2 n_A n_B / n^2 (n = n_A + n_B), so that the full
    /// image's summed luminance variance is this / n. The unit of a pilot's variance (mlt's
    /// direct light: luminanceSquaredDifference of two one-sample images / 2). 0 when not ready.
    double perSampleLuminanceVariance() const;

  private:
    Image previous_;  // the sums after the last run
    Image halfA_;     // the sums of half A's runs
    uint64_t samplesA_ = 0, samplesB_ = 0;
};

}  // namespace partita
