#include "half_split_error.h"

#include <cmath>
#include <stdexcept>

namespace partita {

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
