// partita-eval: measures quality and speed and prints a table; --json F writes the figures.
//   partita-eval throughput --scene S [--width W --height H --spp N --max-depth N --repeats N
//                           --max-threads N] [--json F]
// (`reference` and `quality` arrive with BDPT and the MCMC algorithms.)
#include <CLI/CLI.hpp>

#include <cstdio>
#include <fstream>

#include "throughput.h"

using namespace partita;

int main(int argc, char** argv) {
    CLI::App app{"partita-eval: the Partita evaluation harness"};
    app.require_subcommand(1);
    std::string jsonPath;
    app.add_option("--json", jsonPath, "also write the figures as JSON to this file");
    eval::ThroughputOptions tp;
    auto* throughput = app.add_subcommand(
        "throughput", "path-tracer vs bare Embree ray throughput, thread scaling");
    throughput->add_option("--scene", tp.scene, "a .gltf/.glb scene")->required();
    throughput->add_option("--width", tp.width)->capture_default_str();
    throughput->add_option("--height", tp.height)->capture_default_str();
    throughput->add_option("--spp", tp.spp, "samples per pixel per path-tracer run")
        ->capture_default_str();
    throughput->add_option("--max-depth", tp.maxDepth)->capture_default_str();
    throughput->add_option("--rays", tp.rays, "rays for the bare Embree measurement")
        ->capture_default_str();
    throughput->add_option("--repeats", tp.repeats, "best of this many runs")
        ->capture_default_str();
    throughput
        ->add_option("--max-threads", tp.maxThreads, "largest thread count to measure (0: all)")
        ->capture_default_str();
    throughput->add_option("--camera", tp.camera);
    throughput->add_option("--json", jsonPath, "also write the figures as JSON to this file");
    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "partita-eval: %s (see --help)\n", e.what());
        return 2;
    }
    try {
        nlohmann::json out;
        if (*throughput) out = eval::runThroughput(tp);
        if (!jsonPath.empty()) {
            std::ofstream f(jsonPath);
            f << out.dump(2) << "\n";
            if (!f) throw std::runtime_error("cannot write " + jsonPath);
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "partita-eval: error: %s\n", e.what());
        return 1;
    }
}
