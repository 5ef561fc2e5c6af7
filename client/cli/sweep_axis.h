// One axis of a parameter sweep: `--sweep NAME=V1,V2,...`. NAME is a job parameter:
//   y, radius, k, epsilon, spp, mpp, seconds, max-depth, seed, width, height
// ('_' may stand for '-'). spp, mpp and seconds set the budget (and its kind).
#pragma once

#include <string>
#include <vector>

#include "cli/proto.h"

namespace partita::cli {

struct SweepAxis {
    std::string name;                 // canonical: "max-depth"
    std::vector<std::string> values;  // as written, each checked to parse
};

/// The parameter names a sweep accepts, comma separated (for messages).
std::string sweepParameterNames();

/// Parses "NAME=V1,V2,..."; throws CliError naming the problem.
SweepAxis parseSweepAxis(const std::string& text);

/// Sets parameter `name` of `spec` to `value` (both as parseSweepAxis accepted them).
void applySweepValue(partita::v1::JobSpec& spec, const std::string& name, const std::string& value);

}  // namespace partita::cli
