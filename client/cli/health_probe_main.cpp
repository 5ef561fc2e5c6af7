// partita-health-probe: exits 0 when a partitad answers the standard gRPC health check with
// SERVING, else prints one line and exits 1. For container HEALTHCHECKs and scripts.
//   partita-health-probe [--server HOST:PORT] [--token-file F] [--tls-ca F]
//                        [--tls-server-name NAME] [--timeout S]
#include <CLI/CLI.hpp>

#include <cstdio>

#include "cli/connection.h"
#include "cli/errors.h"
#include "cli/health.h"

using namespace partita::cli;

int main(int argc, char** argv) {
    CLI::App app{"partita-health-probe: is a partitad serving?"};
    ServerOptions opts;
    opts.server = "127.0.0.1:50051";
    double timeout = 5;
    app.add_option("--server", opts.server, "HOST:PORT")->capture_default_str();
    app.add_option("--token-file", opts.tokenFile, "bearer token file");
    app.add_option("--tls-ca", opts.tlsCa, "PEM CA certificate(s): connect with TLS");
    app.add_option("--tls-server-name", opts.tlsServerName, "name to check in the certificate");
    app.add_option("--timeout", timeout, "seconds")->capture_default_str();
    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "partita-health-probe: error: %s\n", oneLine(e.what()).c_str());
        return 2;
    }
    try {
        const std::string token = opts.tokenFile.empty() ? "" : readTokenFile(opts.tokenFile);
        HealthResult r = checkHealth(makeChannel(opts.server, opts), token, timeout);
        if (r.serving) return 0;
        if (r.status.ok()) {
            std::fprintf(stderr, "partita-health-probe: %s is not serving\n", opts.server.c_str());
        } else {
            std::fprintf(stderr, "partita-health-probe: %s: %s (%s)\n", opts.server.c_str(),
                         oneLine(r.status.error_message()).c_str(),
                         statusCodeName(r.status.error_code()).c_str());
        }
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "partita-health-probe: error: %s\n", oneLine(e.what()).c_str());
        return 1;
    }
}
