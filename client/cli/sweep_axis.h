// One axis of a parameter sweep: `--sweep NAME=V1,V2,...`. NAME is a budget (spp, mpp, seconds:
// it sets the budget and its kind) or any declared parameter of the job's algorithm, in the
// CLI's spelling ('_' may stand for '-'): y, radius, k, epsilon, max-depth, seed, width, ...
// (`partita render --algorithm A --help` lists A's). Whether the algorithm takes it is checked
// against the server's declarations (sweep_command.cpp); each value is read with the parameter's
// declaration where this build knows it, else by the server.
#pragma once

#include <string>
#include <vector>

#include "cli/proto.h"

namespace partita::cli {

struct SweepAxis {
    std::string name;                 // the CLI's spelling: "max-depth"
    std::vector<std::string> values;  // as written, each checked to parse where it can be
};

/// Parses "NAME=V1,V2,..." for a job of `algorithm`; throws CliError naming the problem.
SweepAxis parseSweepAxis(const std::string& text, const std::string& algorithm);

/// Sets parameter `name` of `spec` to `value` (both as parseSweepAxis accepted them).
void applySweepValue(partita::v1::JobSpec& spec, const std::string& name, const std::string& value);

}  // namespace partita::cli
