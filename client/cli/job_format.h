// How jobs read on the terminal: state names, progress, durations.
#pragma once

#include <string>

#include "algorithm.h"
#include "cli/proto.h"

namespace partita::cli {

/// "queued", "loading", "prepass", "rendering", "done", "failed", "cancelled".
std::string stateName(partita::v1::JobState state);
bool isTerminal(partita::v1::JobState state);

/// The service's progress as the core's, for ProgressBar.
RenderProgress toRenderProgress(const partita::v1::Progress& progress);

/// "42.0%", "1.2 k samples", "done", "-".
std::string progressText(const partita::v1::Job& job);

/// Render seconds of a finished job: its "seconds" statistic, else finished - started; NaN when
/// unknown.
double jobSeconds(const partita::v1::Job& job);

}  // namespace partita::cli
