// What one job adds to the daemon's memory, estimated before it runs, so that a legal-looking
// request (8192x8192 with 1024 type layers) is refused instead of getting the daemon killed by the
// kernel with every running job. An upper estimate from the settings alone, checked against
// measured peaks (server/README.md "Memory"):
//
// - the accumulation film: combined sums (12 B/pixel, tiles padded to 16x16) plus the sparse
//   per-type blocks (an allowance of 24 B/pixel); guided keeps one film per render thread,
//   partitioned one per partition (K + 1, the complement's type blocks growing with the budget
//   like mlt's), bdpt three; bdpt's and mlt's type blocks grow with the budget (counted
//   apart), and mlt adds its bootstrap's candidates and its chains' splats and states,
//   partitioned its pre-pass's half-B records (40 B, ~13 a sample, half the samples) and the
//   same chains;
// - every resolved layer (combined, up to max_type_layers types, "other") is a dense float RGB
//   image, 12 B/pixel, alive in up to three copies at the peak: the latest preview frame the job
//   holds for watchers, the final image, and the EXR writer's interleaved buffer; plus one
//   serialized raw preview shared by raw watchers (12 B/pixel) and its PNGs (~1 B/pixel);
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

/// `environment`: the header of the job's environment image (all zero without one).
MemoryEstimate estimateJobMemory(const std::string& algorithm, const RenderSettings& settings,
                                 uint64_t sceneBytes, int renderThreads,
                                 const ImageHeader& environment = {});

/// "512 KiB", "1.3 GiB".
std::string humanBytes(double bytes);

/// The machine's physical memory in bytes (0 when unknown).
uint64_t physicalMemoryBytes();

}  // namespace partita::server
