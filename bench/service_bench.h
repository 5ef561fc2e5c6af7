// `partita-eval service`: what the service costs over rendering in-process (DESIGN.md "Quality
// and speed targets": >= 95% of the in-process throughput with previews every second, the first
// preview within 1 s of rendering), measured against a private partitad started for the run:
//   1. one render in-process and through the daemon (with a WatchJob stream taking PNG previews
//      the whole time), interleaved --repeats times, and their samples/s;
//   2. the time from SubmitJob to the first preview frame of those daemon jobs;
//   3. the latency of --jobs SubmitJob calls of tiny jobs (deleted again afterwards).
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

namespace partita::eval {

struct ServiceOptions {
    std::string scene = "scenes/cornell/cornell.gltf";  // uploaded with each daemon job
    int width = 320, height = 240;
    int spp = 192;  // about 7 s in-process on the 2 cores of the development machine
    uint64_t seed = 1;
    int maxDepth = 16;
    int threads = 0;  // in-process pool and partitad --threads (0: the hardware's)
    int repeats = 3;  // interleaved in-process / daemon pairs; best and median reported
    double previewInterval = 1.0;
    int jobs = 200;                      // tiny jobs for the submit latency
    std::string smallScene = "cornell";  // by name, from the daemon's scene root
};

/// Runs the measurement, prints a table to stdout and returns the figures as JSON: scene, width,
/// height, spp, threads, in_process_samples_per_s, daemon_samples_per_s, ratio,
/// first_preview_ms, submit_latency_ms {mean, p50, p95, p99, max}, jobs (and more detail).
nlohmann::json runServiceBench(const ServiceOptions& options);

}  // namespace partita::eval
