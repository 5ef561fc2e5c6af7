// The error of a partitioned render (`partitioned`, `guided`) estimated from the render itself
// (issue #26), per partition and combined. A partition with chains: its chains' two halves
// (ChainRunner::halvesError, the even and the odd chains of its group) and its b's relative
// error from the pre-pass (Partition::bError, a scale of its whole image:
// ErrorSums::addScaleVariance). A per-pixel partition: the per-pixel pilot's per-sample
// variance of its image over its samples per pixel (PerPixelPilot::varianceRgb). The combined
// image (Eq. 9) is the sum of the partitions' images, its error the sum of theirs: the parts are
// taken as independent, which leaves out what they share (one per-pixel sample estimates every
// per-pixel partition; the b_i come from one half B).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "half_split_error.h"
#include "image.h"
#include "mcmc/chain_error_monitor.h"
#include "partition/partition.h"

namespace partita {

class ChainRunner;

/// The progress value and statistic of partition g's estimated relative RMSE (of its own image).
std::string partitionErrorName(size_t g);

/// The estimate: `pixelImages`/`pixelVarianceRgb`/`pixelSpp` for the per-pixel partitions
/// (unused when none is); `runner` the chains' (null before any chain runs: a partition with
/// chains then has no estimate). A part without an estimate yet (a half of its chains without a
/// mutation, a group of one chain, a per-pixel partition without a pilot) has none, and then
/// neither has the combined image.
ChainErrorMonitor::Estimate estimatePartitionError(const std::vector<Partition>& partitions,
                                                   const ChainRunner* runner,
                                                   const std::vector<Image>& pixelImages,
                                                   const std::vector<double>& pixelVarianceRgb,
                                                   uint64_t pixelSpp);

}  // namespace partita
