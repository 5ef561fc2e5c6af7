// The render options every front end accepts (DESIGN.md "Command lines"), bound to CLI11 and
// made from the declared parameters (params/job_parameters.h): a flag --NAME for each shared
// parameter and for each parameter of every registered algorithm, --param NAME=VALUE for any
// declared parameter (also one this build does not know, for a server that does), and the
// budget flags. `--algorithm A --help` lists A's own parameters with defaults and ranges.
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

#include "params/parameter_values.h"
#include "render_settings.h"

namespace partita {

struct RenderOptions {
    /// The shared parameters given on the command line are applied here as they are parsed (a
    /// caller may set other defaults before parsing); the algorithm's in finalizeRenderOptions.
    RenderSettings settings;
    std::string algorithm = "pt";
    int threads = 0;  // 0 = all hardware threads
    std::optional<double> spp, mpp, seconds;
    /// Every parameter given on the command line, by canonical name, as its text.
    ParameterValues given;
};

/// Adds the flags. `helpAlgorithm` (algorithmInArguments), when it names a registered
/// algorithm, keeps only its parameters in --help (the others are still accepted, and refused
/// with the core's message when they are not the algorithm's).
void addRenderOptions(CLI::App& app, RenderOptions& options, const std::string& helpAlgorithm = "");

/// The value of --algorithm on a command line ("" when absent): read before parsing, so that
/// --help can show that algorithm's parameters.
std::string algorithmInArguments(int argc, const char* const* argv);

/// Resolves the budget flags into settings.budget/budgetKind, applies the given parameters to
/// the algorithm (settings.parameters) and validates everything with the core's rules (also
/// the algorithm name against the registry). Returns "" or one line saying what is wrong.
std::string finalizeRenderOptions(RenderOptions& options);

}  // namespace partita
