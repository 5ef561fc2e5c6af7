// The measurements of `partita-eval quality`, per algorithm and seed, and their aggregation.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "image_metrics.h"
#include "render_settings.h"

namespace partita::eval {

struct SeedRun {
    uint64_t seed = 0;
    std::vector<LayerError> errors;  // "combined" first, then layers in both render and reference
    double wallSeconds = 0;
    double unitsPerPixel = 0;  // samples or mutations per pixel actually done
    std::string unit;          // "samples" or "mutations"
    std::optional<double> acceptance;
};

struct AlgorithmRun {
    std::string algorithm;
    RenderSettings settings;  // the budget it ran under (seed of the first run)
    std::vector<SeedRun> runs;
    double peakRssMb = 0;          // the process's peak while this algorithm's renders ran
    double rssIncreaseMb = 0;      // that peak over the resident memory just before them
    bool peakPerAlgorithm = true;  // false: the peak could not be reset (lifetime peak)
};

/// The reference's own error per layer, read from its metadata (empty when it has none).
using ReferenceErrors = std::map<std::string, LayerError>;

/// One entry of "results": the DESIGN.md fields and per-layer figures.
nlohmann::json resultJson(const AlgorithmRun& run, const std::vector<std::string>& layerOrder,
                          const ReferenceErrors& referenceErrors);

/// The two tables on stdout: one row per algorithm, then one row per type layer.
void printQualityTables(const std::vector<AlgorithmRun>& runs,
                        const std::vector<std::string>& layerOrder,
                        const ReferenceErrors& referenceErrors, size_t tableLayers);

/// Mean wall seconds over the seeds of one algorithm.
double meanWallSeconds(const AlgorithmRun& run);

}  // namespace partita::eval
