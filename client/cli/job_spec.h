// The render flags of DESIGN.md ("Command lines") turned into a JobSpec. The flags themselves
// come from tools/frontend/render_options.h, so partita and partita-local accept the same ones;
// the CLI adds --label, --priority and --preview-interval. Only flags given on the command line
// are set in the JobSpec: everything else takes the server's defaults.
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

#include "cli/proto.h"
#include "frontend/render_options.h"

namespace partita::cli {

struct JobFlags {
    RenderOptions render;
    std::string label;
    int priority = 0;
    std::optional<double> previewInterval;
};

void addJobOptions(CLI::App& app, JobFlags& flags);

/// The JobSpec of the flags given to `app` (scene not set). Throws CliError on invalid values.
partita::v1::JobSpec makeJobSpec(const CLI::App& app, const JobFlags& flags);

/// Checks the spec's values with the core's limits (validateSettings): "" or one line.
std::string validateJobSpec(const partita::v1::JobSpec& spec);

}  // namespace partita::cli
