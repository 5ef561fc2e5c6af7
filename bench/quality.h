// `partita-eval quality`: renders a scene with each algorithm over several seeds and measures
// the error against a reference (RMSE and relMSE, combined and per type layer), wall time,
// samples or mutations per second, acceptance and peak memory; optionally at equal time.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "frontend/render_options.h"

namespace partita::eval {

struct QualityOptions {
    std::string scene, reference;
    std::vector<std::string> algorithms;
    int seeds = 4;           // seeds --seed, --seed + 1, ...
    bool equalTime = false;  // every algorithm after the first gets the first's mean wall time
    bool sizeGiven = false;  // --width/--height were given (else the reference's size is used)
    bool quiet = false;
    int tableLayers = 10;  // type layers in the printed table (the JSON has all)
    RenderOptions render;  // budget, size, max depth ...; its algorithm is ignored
};

/// Prints the tables and returns the figures as JSON (DESIGN.md: scene, width, height,
/// results[{algorithm, spp|mpp|seconds, seeds, rmse_mean, rmse_std, relmse_mean, seconds_mean,
/// rate, acceptance, peak_rss_mb}], plus per-layer figures).
nlohmann::json runQuality(QualityOptions options);

}  // namespace partita::eval
