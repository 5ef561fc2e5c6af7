#include "half_split_error.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace partita {

void ErrorSums::addScaleVariance(double relativeVariance) {
    if (relativeVariance > 0 && std::isfinite(relativeVariance))
        variance += relativeVariance * squares;
}

void ErrorSums::add(const ErrorSums& part) {
    if (count > 0 && part.count > 0 && count != part.count)
        throw std::invalid_argument("ErrorSums: the parts are of different images");
    variance += part.variance;
    value += part.value;
    squares = 0;
    if (part.count > 0) count = part.count;
}

double ErrorSums::relativeRmse() const {
    if (!(count > 0) || !(value > 0)) return 0;
    return std::sqrt(variance / count) / (value / count);
}

ErrorSums imageErrorSums(const Image& image, double variance) {
    ErrorSums out;
    out.variance = variance;
    for (float v : image.rgb) {
        out.value += double(v);
        out.squares += double(v) * double(v);
    }
    out.count = double(image.rgb.size());
    return out;
}

namespace {

/// The error sums of two halves given pixel-channel by pixel-channel: halfValue(i) returns
/// half A's and half B's estimates of pixel-channel i (weights n_a, n_b > 0).
template <class HalfValue>
ErrorSums sumHalves(size_t count, double weightA, double weightB, const HalfValue& halfValue) {
    ErrorSums out;
    const double n = weightA + weightB;
    const double varianceFactor = weightA * weightB / (n * n);
    for (size_t i = 0; i < count; ++i) {
        const auto [x, y] = halfValue(i);
        const double mean = (weightA * x + weightB * y) / n;
        out.variance += (x - y) * (x - y) * varianceFactor;
        out.value += mean;
        out.squares += mean * mean;
    }
    out.count = double(count);
    return out;
}

}  // namespace

double relativeVarianceOfMean(double sum, double sumSquares, double n) {
    if (!(sum > 0) || !(n > 0)) return INFINITY;
    return std::max(0.0, sumSquares / (sum * sum) - 1.0 / n);
}

ErrorSums halvesError(const Image& a, const Image& b, double weightA, double weightB) {
    if (a.rgb.size() != b.rgb.size())
        throw std::invalid_argument("halvesError: the halves differ in size");
    if (!(weightA > 0) || !(weightB > 0)) return {};
    return sumHalves(a.rgb.size(), weightA, weightB, [&](size_t i) {
        return std::pair<double, double>(double(a.rgb[i]), double(b.rgb[i]));
    });
}

void HalfSplitError::addRun(const Image& sums, uint64_t samples, bool toA) {
    if (previous_.empty()) {
        previous_ = Image(sums.width, sums.height);
        halfA_ = Image(sums.width, sums.height);
    }
    if (sums.rgb.size() != previous_.rgb.size())
        throw std::invalid_argument("HalfSplitError: the image changed size");
    for (size_t i = 0; i < sums.rgb.size(); ++i) {
        if (toA) halfA_.rgb[i] += sums.rgb[i] - previous_.rgb[i];
        previous_.rgb[i] = sums.rgb[i];
    }
    (toA ? samplesA_ : samplesB_) += samples;
}

void HalfSplitError::setInterleaved(Image totalSums, const Image& oddSums, uint64_t samples) {
    if (totalSums.rgb.size() != oddSums.rgb.size())
        throw std::invalid_argument("HalfSplitError: the halves differ in size");
    previous_ = std::move(totalSums);
    halfA_ = Image(previous_.width, previous_.height);
    for (size_t i = 0; i < previous_.rgb.size(); ++i)
        halfA_.rgb[i] = previous_.rgb[i] - oddSums.rgb[i];
    samplesA_ = (samples + 1) / 2;  // the even indices of [0, samples)
    samplesB_ = samples / 2;
}

ErrorSums HalfSplitError::errorSums() const {
    if (!ready()) return {};
    const double nA = double(samplesA_), nB = double(samplesB_);
    return sumHalves(previous_.rgb.size(), nA, nB, [&](size_t i) {
        const double a = double(halfA_.rgb[i]), total = double(previous_.rgb[i]);
        return std::pair<double, double>(a / nA, (total - a) / nB);
    });
}

double pooledVariance(double pilot, double pilotSamples, double own, double samples) {
    if (!(samples >= 2) || !(own > 0)) return pilot;
    return (pilotSamples * pilot + samples * own) / (pilotSamples + samples);
}

double HalfSplitError::perSampleLuminanceVariance() const {
    if (!ready()) return 0;
    const double nA = double(samplesA_), nB = double(samplesB_), n = nA + nB;
    double sum = 0;
    for (size_t i = 0; i + 2 < previous_.rgb.size(); i += 3) {
        const Rgb a(halfA_.rgb[i], halfA_.rgb[i + 1], halfA_.rgb[i + 2]);
        const Rgb total(previous_.rgb[i], previous_.rgb[i + 1], previous_.rgb[i + 2]);
        const double d = double(luminance(a)) / nA - double(luminance(total - a)) / nB;
        sum += d * d;
    }
    return sum * nA * nB / n;
}

double HalfSplitError::relativeRmse() const { return errorSums().relativeRmse(); }

}  // namespace partita
