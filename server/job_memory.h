// What one job adds to the daemon's memory, estimated before it runs, so that a legal-looking
// request (8192x8192 with 1024 type layers) is refused instead of getting the daemon killed by the
// kernel with every running job. An upper estimate from the settings alone, checked against
// measured peaks (server/README.md "Memory"):
//
// - the accumulation film: exact sums, 24 B/pixel (tiles padded to 16x16), the combined ones
//   and those of the kept type layers and "other" (a bound: `layers` + 1 buffers, counted at
//   the coverage measured on bathroom); one film for pt, bdpt and mlt, one per partition
//   (K + 1) without type layers for partitioned and guided; pt's and bdpt's layer survey;
//   bdpt's light-tracing splats of a batch of tiles; mlt's bootstrap candidates and its chains'
//   splats and states; partitioned's pre-pass half-B records (40 B, ~13 a sample, half the
//   samples) and the same chains;
// - every resolved layer (combined, the type layers, "other") is a dense float RGB image,
//   12 B/pixel: with previews, two frames (the latest the job holds, and an older one a slow
//   watcher still holds) with their PNGs, and raw watchers' frames (the float32 pixels of
//   every layer: the message, its serialized copy, and the copy a watcher is still sending),
//   counted up to the server's raw preview limit, above which a raw watch is refused; and the
//   final image, which is made as the film is consumed (the larger of the film and the final
//   image counts, not their sum);
// - partitions (K images of 12 B/pixel; partitioned K + 1) for the partitioned methods;
// - the scene: four times its file bytes (parsed arrays, render copies, BVH).
#pragma once

#include <cstdint>
#include <string>

#include "image_io.h"
#include "render_settings.h"

namespace partita::server {

struct MemoryEstimate {
    uint64_t bytes = 0;
    std::string breakdown;  // "film 36 B/pixel, 34 layers x 49 B/pixel, scene 1.2 MiB"
};

/// `environment`: the header of the job's environment image (all zero without one);
/// `rawPreviewLimit`: the largest raw preview frame a watcher may ask for (0: none).
MemoryEstimate estimateJobMemory(const std::string& algorithm, const RenderSettings& settings,
                                 uint64_t sceneBytes, int renderThreads,
                                 const ImageHeader& environment = {}, uint64_t rawPreviewLimit = 0);

/// Bytes of one raw preview frame of the job: every layer its frames carry (the combined one,
/// the type layers and "other", or the partitions) as float32 RGB.
uint64_t rawPreviewBytes(const std::string& algorithm, const RenderSettings& settings);

/// "512 KiB", "1.3 GiB".
std::string humanBytes(double bytes);

/// The machine's physical memory in bytes (0 when unknown).
uint64_t physicalMemoryBytes();

}  // namespace partita::server
