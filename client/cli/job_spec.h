// The render flags of DESIGN.md ("Command lines") turned into a JobSpec. The flags themselves
// come from tools/frontend/render_options.h (made from the declared parameters), so partita and
// partita-local accept the same ones; the CLI adds --label and --priority. Only parameters
// given on the command line travel, by name and as their text, in JobSpec.parameters:
// everything else takes the server's defaults, and the server validates (the CLI first runs the
// same core validation where this build knows the algorithm, so that a mistake is caught before
// a scene is uploaded).
#pragma once

#include <CLI/CLI.hpp>

#include <string>

#include "cli/proto.h"
#include "frontend/render_options.h"

namespace partita::cli {

struct JobFlags {
    RenderOptions render;
    std::string label;
    int priority = 0;
};

/// `helpAlgorithm`: as addRenderOptions'.
void addJobOptions(CLI::App& app, JobFlags& flags, const std::string& helpAlgorithm = "");

/// The JobSpec of the flags given to `app` (scene not set). Throws CliError on invalid values.
partita::v1::JobSpec makeJobSpec(const CLI::App& app, const JobFlags& flags);

/// Sets parameter `name` (either spelling) of `spec` to `text`, as the server will read it.
void setParameter(partita::v1::JobSpec& spec, const std::string& name, const std::string& text);

/// The settings `spec` asks for as the core resolves them (defaults for what it does not give),
/// or "" in `error` when fine; an algorithm this build does not know resolves only the shared
/// parameters it gives (the server checks the rest).
RenderSettings settingsOfSpec(const partita::v1::JobSpec& spec, std::string& error);

/// Checks the spec's values with the core's rules (validateJob, without the server's limits,
/// which Session::checkLimits reads from GetServerInfo): "" or one line.
std::string validateJobSpec(const partita::v1::JobSpec& spec);

}  // namespace partita::cli
