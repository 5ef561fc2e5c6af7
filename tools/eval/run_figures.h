// Figures `partita-eval quality` derives from the renders' statistics (RenderStats values, one
// map per seed): means over seeds, the cost of one sample or mutation, and per-mutation
// acceptance (mlt reports acceptance_<name> and proposed_<name> per mutation type).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace partita::eval {

using Statistics = std::map<std::string, double>;

/// Per statistic, its mean over the seeds whose render reported it.
Statistics meanStatistics(const std::vector<Statistics>& perSeed);

/// Seconds of sampling per sample (pt, bdpt) or per mutation (mlt): `render_seconds` (pt and
/// bdpt: the sampling passes; mlt: the chains, without the bootstrap) over the units done
/// (units per pixel times pixels). Null when either is missing or nothing was done.
std::optional<double> secondsPerUnit(const Statistics& stats, double unitsPerPixel, double pixels);

/// Per mutation type (the names after "acceptance_"), the mean acceptance over the seeds that
/// proposed it at least once (`proposed_<name>` > 0; without that statistic every seed counts);
/// null for a type that no seed proposed.
std::map<std::string, std::optional<double>> acceptancePerMutation(
    const std::vector<Statistics>& perSeed);

/// One render's acceptance over all mutation types: its `acceptance` if reported, else the
/// acceptances weighted by their proposals; null when it proposed nothing.
std::optional<double> overallAcceptance(const Statistics& stats);

}  // namespace partita::eval
