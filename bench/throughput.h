// `partita-eval throughput`: ray throughput of the path tracer against bare Embree on the same
// scene, and path-tracer samples/s per thread count, measured side by side in one run.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace partita::eval {

struct ThroughputOptions {
    std::string scene;
    int width = 320, height = 240;
    int spp = 4;  // per path-tracer run
    int maxDepth = 16;
    int rays = 2'000'000;  // for the bare Embree measurement
    int repeats = 7;       // rounds (kernel, then path tracer): median ratio, best-of rates
    int maxThreads = 0;    // thread counts 1, 2, 4, ... up to this (0: the hardware's)
    std::string camera;
};

/// Runs the measurement, prints a table to stdout and returns the figures as JSON
/// (DESIGN.md: scene, embree_rays_per_s, pt_rays_per_s, ratio, threads[{n, samples_per_s}]).
nlohmann::json runThroughput(const ThroughputOptions& options);

}  // namespace partita::eval
