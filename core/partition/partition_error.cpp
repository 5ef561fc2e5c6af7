#include "partition/partition_error.h"

#include "mcmc/chain_runner.h"

namespace partita {

std::string partitionErrorName(size_t g) {
    return "partition_" + std::to_string(g) + "_error_estimate";
}

namespace {

/// Partition g's error sums; count 0 when it has no estimate.
ErrorSums partError(size_t g, const Partition& p, const ChainRunner* runner,
                    const std::vector<Image>& pixelImages,
                    const std::vector<double>& pixelVarianceRgb, uint64_t pixelSpp) {
    if (p.perPixel) {
        if (g >= pixelImages.size() || g >= pixelVarianceRgb.size() || pixelSpp == 0 ||
            pixelImages[g].empty())
            return {};
        return imageErrorSums(pixelImages[g], pixelVarianceRgb[g] / double(pixelSpp));
    }
    if (!runner) return {};
    ErrorSums sums = runner->halvesError(uint32_t(g));
    sums.addScaleVariance(p.bError * p.bError);
    return sums;
}

}  // namespace

ChainErrorMonitor::Estimate estimatePartitionError(const std::vector<Partition>& partitions,
                                                   const ChainRunner* runner,
                                                   const std::vector<Image>& pixelImages,
                                                   const std::vector<double>& pixelVarianceRgb,
                                                   uint64_t pixelSpp) {
    ChainErrorMonitor::Estimate out;
    ErrorSums total;
    bool complete = !partitions.empty();
    for (size_t g = 0; g < partitions.size(); ++g) {
        const ErrorSums part =
            partError(g, partitions[g], runner, pixelImages, pixelVarianceRgb, pixelSpp);
        if (!(part.count > 0)) {
            complete = false;
            continue;
        }
        out.parts[partitionErrorName(g)] = part.relativeRmse();
        total.add(part);
    }
    if (complete) out.combined = total.relativeRmse();
    return out;
}

}  // namespace partita
