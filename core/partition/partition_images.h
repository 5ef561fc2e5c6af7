// The pre-pass image of each partition (paper Sec. 5.1.1): the guided proposal thresholds a
// denoised copy of it (Eq. 17, core/guide/denoise.h) to tell where the partition's paths land.
// Half B's records (prepass.h) carry the pixel each path lands in, so the images cost no rays.
#pragma once

#include <vector>

#include "partition/partition.h"
#include "partition/prepass.h"

namespace partita {

/// Per partition, the luminance image of half B's paths that belong to it: each candidate's weight
/// added at its pixel, times (pixel count / samplesB) so that the image's mean is b_i. One
/// std::vector<float> (width*height) per partition, in the order of `partitions`. (When the
/// pre-pass's memory budget truncated half B's records, the images hold the records kept.)
std::vector<std::vector<float>> partitionPrepassImages(const PrepassResult& prepass,
                                                       const std::vector<Partition>& partitions,
                                                       int width, int height);

}  // namespace partita
