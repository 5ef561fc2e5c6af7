#include "half_split_error.h"

#include <cmath>
#include <stdexcept>

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

ErrorSums halvesError(const Image& a, const Image& b, double weightA, double weightB) {
    if (a.rgb.size() != b.rgb.size())
        throw std::invalid_argument("halvesError: the halves differ in size");
    ErrorSums out;
    if (!(weightA > 0) || !(weightB > 0)) return out;
    const double n = weightA + weightB;
    const double varianceFactor = weightA * weightB / (n * n);
    for (size_t i = 0; i < a.rgb.size(); ++i) {
        const double x = double(a.rgb[i]), y = double(b.rgb[i]);
        const double mean = (weightA * x + weightB * y) / n;
        out.variance += (x - y) * (x - y) * varianceFactor;
        out.value += mean;
        out.squares += mean * mean;
    }
    out.count = double(a.rgb.size());
    return out;
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

ErrorSums HalfSplitError::errorSums() const {
    if (!ready()) return {};
    const double nA = double(samplesA_), nB = double(samplesB_);
    Image a(previous_.width, previous_.height), b(previous_.width, previous_.height);
    for (size_t i = 0; i < previous_.rgb.size(); ++i) {
        a.rgb[i] = float(double(halfA_.rgb[i]) / nA);
        b.rgb[i] = float(double(previous_.rgb[i] - halfA_.rgb[i]) / nB);
    }
    return halvesError(a, b, nA, nB);
}

double HalfSplitError::relativeRmse() const {
    if (!ready()) return 0;
    const double nA = double(samplesA_), nB = double(samplesB_), n = nA + nB;
    const double varianceFactor = nA * nB / (n * n);
    double variance = 0, mean = 0;
    for (size_t i = 0; i < previous_.rgb.size(); ++i) {
        const double a = double(halfA_.rgb[i]), total = double(previous_.rgb[i]);
        const double difference = a / nA - (total - a) / nB;
        variance += difference * difference * varianceFactor;
        mean += total / n;
    }
    if (!(mean > 0)) return 0;
    // Both sums are over the same pixel-channels: the ratio of the means is the ratio of sums.
    const double count = double(previous_.rgb.size());
    return std::sqrt(variance / count) / (mean / count);
}

}  // namespace partita
