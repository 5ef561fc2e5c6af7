// Which contributions a per-pixel film keeps, and under which key (the per-pixel partitions of
// partition/per_pixel_partitions.h): given a contribution's path type and the index of the pixel
// sample that made it, returns false to drop it, or true and (optionally) rewrites the type into
// the key its film adds it under (the pilot keeps the two sample parities apart). Empty: every
// contribution, under its own type.
//
// A restriction to a set of types keeps MIS exact: every strategy that can make a path makes it
// with the same type, so the weights of the strategies of a kept path still sum to one (the
// restricted image is the full image's layers of those types).
#pragma once

#include <cstdint>
#include <functional>

#include "path_type.h"

namespace partita {

using ContributionKey = std::function<bool(PathType& type, uint64_t sample)>;

}  // namespace partita
