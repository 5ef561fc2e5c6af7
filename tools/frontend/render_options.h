// The render options every front end accepts (DESIGN.md "Command lines"), bound to CLI11.
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

#include "render_settings.h"

namespace partita {

struct RenderOptions {
    RenderSettings settings;
    std::string algorithm = "pt";
    int threads = 0;  // 0 = all hardware threads
    std::optional<double> spp, mpp, seconds;
};

void addRenderOptions(CLI::App& app, RenderOptions& options);

/// Resolves the budget flags into settings.budget/budgetKind and validates everything (also the
/// algorithm name against the registry). Returns "" or one line saying what is wrong.
std::string finalizeRenderOptions(RenderOptions& options);

}  // namespace partita
