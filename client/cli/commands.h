// The subcommands of `partita`, one file each. Each add*Command registers its subcommand and
// its options with the app and returns how to run it once the command line is parsed.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>

#include "cli/session.h"

namespace partita::cli {

struct Command {
    CLI::App* app = nullptr;
    std::function<int()> run;
};

Command addRenderCommand(CLI::App& app, const GlobalOptions& global);
Command addWatchCommand(CLI::App& app, const GlobalOptions& global);
Command addGetCommand(CLI::App& app, const GlobalOptions& global);
Command addCancelCommand(CLI::App& app, const GlobalOptions& global);
Command addJobsCommand(CLI::App& app, const GlobalOptions& global);
Command addSweepCommand(CLI::App& app, const GlobalOptions& global);
Command addCompareCommand(CLI::App& app, const GlobalOptions& global);

}  // namespace partita::cli
