// partita: the command-line client of the Partita render service (DESIGN.md "Command lines").
//   partita [--server HOST:PORT] [--token-file F] [--tls-ca F] [-q] COMMAND ...
// COMMAND: render, watch, get, cancel, jobs, sweep, compare. With no --server, commands that
// need a server run against a private partitad started for the command (private_daemon.h).
// Exit status: 0 on success; otherwise one line "partita: error: <message> (<GRPC_CODE>)" on
// stderr and 1 (2 for a bad command line, 130 when interrupted).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <vector>

#include "cli/commands.h"
#include "cli/errors.h"
#include "cli/signals.h"
#include "frontend/render_options.h"

#ifndef PARTITA_VERSION
#define PARTITA_VERSION "0.0.0"
#endif

using namespace partita::cli;

int main(int argc, char** argv) {
    CLI::App app{"partita: submit, watch and compare renders on a Partita render service"};
    app.require_subcommand(1);
    app.set_version_flag("--version", PARTITA_VERSION);
    app.fallthrough();
    GlobalOptions global;
    global.helpAlgorithm = partita::algorithmInArguments(argc, argv);
    app.add_option("--server", global.server.server,
                   "HOST:PORT of a partitad (default: start a private one for this command)");
    app.add_option("--token-file", global.server.tokenFile,
                   "file with the bearer token the server expects");
    app.add_option("--tls-ca", global.server.tlsCa, "PEM CA certificate(s): connect with TLS");
    app.add_option("--tls-server-name", global.server.tlsServerName,
                   "name to check in the server's certificate (default: the HOST of --server)");
    app.add_flag("-q,--quiet", global.quiet, "no progress bar, no informational lines");

    const std::vector<Command> commands = {
        addRenderCommand(app, global),  addWatchCommand(app, global), addGetCommand(app, global),
        addCancelCommand(app, global),  addJobsCommand(app, global),  addSweepCommand(app, global),
        addCompareCommand(app, global),
    };

    // CLI11 reports an unknown command as "a subcommand is required": name it instead.
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--server" || arg == "--token-file" || arg == "--tls-ca" ||
            arg == "--tls-server-name") {
            ++i;
            continue;
        }
        if (arg.empty() || arg[0] == '-') continue;
        bool known = false;
        std::string names;
        for (const auto& command : commands) {
            known = known || command.app->get_name() == arg;
            names += (names.empty() ? "" : ", ") + command.app->get_name();
        }
        if (known) break;
        std::fprintf(stderr, "partita: error: unknown command '%s' (commands: %s; see --help)\n",
                     arg.c_str(), names.c_str());
        return 2;
    }

    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "partita: error: %s (see --help)\n", oneLine(e.what()).c_str());
        return 2;
    }

    installInterruptHandler();
    try {
        for (const auto& command : commands)
            if (command.app->parsed()) return command.run();
        return 2;
    } catch (const CliError& e) {
        const std::string code = e.code().empty() ? std::string() : " (" + e.code() + ")";
        std::fprintf(stderr, "partita: error: %s%s\n", oneLine(e.what()).c_str(), code.c_str());
        return e.exitCode();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "partita: error: %s\n", oneLine(e.what()).c_str());
        return 1;
    }
}
