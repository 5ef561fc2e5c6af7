// The measurements of `partita-eval quality`, per algorithm and seed, and their aggregation.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "eval/partition_error.h"
#include "eval/run_figures.h"
#include "image_metrics.h"
#include "render_settings.h"

namespace partita::eval {

struct SeedRun {
    uint64_t seed = 0;
    std::vector<LayerError> errors;  // "combined" first, then layers in both render and reference
    double wallSeconds = 0;
    double unitsPerPixel = 0;                   // samples or mutations per pixel actually done
    std::string unit;                           // "samples" or "mutations"
    std::optional<double> acceptance;           // over all mutation types (overallAcceptance)
    Statistics stats;                           // the render's statistics (RenderStats values)
    std::map<std::string, std::string> labels;  // and its labels (partition types, pre-pass)
    /// partitioned: each partition's error against its reference (eval/partition_error.h).
    std::vector<PartitionError> partitions;
};

struct AlgorithmRun {
    std::string algorithm;
    RenderSettings settings;  // the budget it ran under (seed of the first run)
    std::vector<SeedRun> runs;
    double peakRssMb = 0;          // the process's peak while this algorithm's renders ran
    double rssIncreaseMb = 0;      // that peak over the resident memory just before them
    bool peakPerAlgorithm = true;  // false: the peak could not be reset (lifetime peak)
    /// The daemon's memory estimate of one such job (server/job_memory.h), when built with the
    /// service.
    std::optional<double> estimateMb;
    std::string estimateBreakdown;
    /// An algorithm without partitions measured on the partitions of another's render of the
    /// same seed (its name; empty when the partitions are the algorithm's own).
    std::string partitionsOf;
};

/// The reference's own error per layer, read from its metadata (empty when it has none).
using ReferenceErrors = std::map<std::string, LayerError>;

/// One entry of "results": the DESIGN.md fields, per-layer figures, the statistics' means, and
/// the cost per unit and rays/s relative to `baseline` (the run's first algorithm).
nlohmann::json resultJson(const AlgorithmRun& run, const AlgorithmRun& baseline,
                          const std::vector<std::string>& layerOrder,
                          const ReferenceErrors& referenceErrors);

/// The tables on stdout: one row per algorithm; its cost per sample or mutation and rays/s
/// against the first algorithm's; acceptance per mutation type (when an algorithm has
/// mutations); one row per type layer.
void printQualityTables(const std::vector<AlgorithmRun>& runs,
                        const std::vector<std::string>& layerOrder,
                        const ReferenceErrors& referenceErrors, size_t tableLayers);

/// Mean wall seconds over the seeds of one algorithm.
double meanWallSeconds(const AlgorithmRun& run);

}  // namespace partita::eval
