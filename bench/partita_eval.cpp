// partita-eval: measures quality and speed and prints a table; --json F writes the figures.
//   partita-eval throughput --scene S [--width W --height H --spp N --max-depth N --repeats N
//                           --max-threads N] [--json F]
//   partita-eval service [--scene S --width W --height H --spp N --seed N --max-depth N
//                        --threads N --repeats N --preview-interval S --jobs N
//                        --small-scene NAME] [--json F]      (built with PARTITA_BUILD_SERVICE)
//   partita-eval reference --scene S (--spp N | --mpp N) [--out ref.exr] [--cache DIR]
//                          [--no-cache] [--force] [render options] [--json F]
//   partita-eval quality --scene S --algorithms a,b,... (--spp N | --mpp N | --seconds S)
//                        --seeds K --reference ref.exr [--equal-time] [render options] [--json F]
#include <CLI/CLI.hpp>

#include <cstdio>
#include <fstream>

#include "file_io.h"
#include "quality.h"
#include "reference.h"
#include "throughput.h"
#ifdef PARTITA_EVAL_SERVICE
#include "service_bench.h"
#endif

using namespace partita;

#ifdef PARTITA_EVAL_SERVICE
static CLI::App* addServiceCommand(CLI::App& app, eval::ServiceOptions& o, std::string& json) {
    auto* cmd = app.add_subcommand(
        "service", "daemon vs in-process throughput, first preview, submit latency");
    cmd->add_option("--scene", o.scene, "a .gltf/.glb scene (uploaded with each daemon job)")
        ->capture_default_str();
    cmd->add_option("--width", o.width)->capture_default_str();
    cmd->add_option("--height", o.height)->capture_default_str();
    cmd->add_option("--spp", o.spp, "samples per pixel of each render")->capture_default_str();
    cmd->add_option("--seed", o.seed)->capture_default_str();
    cmd->add_option("--max-depth", o.maxDepth)->capture_default_str();
    cmd->add_option("--threads", o.threads, "render threads in-process and in partitad (0: all)")
        ->capture_default_str();
    cmd->add_option("--repeats", o.repeats, "interleaved in-process/daemon pairs")
        ->capture_default_str();
    cmd->add_option("--preview-interval", o.previewInterval, "seconds, for the daemon jobs")
        ->capture_default_str();
    cmd->add_option("--jobs", o.jobs, "tiny jobs submitted for the submit latency")
        ->capture_default_str();
    cmd->add_option("--small-scene", o.smallScene,
                    "scene name (daemon's scene root) of the tiny jobs")
        ->capture_default_str();
    cmd->add_option("--json", json, "also write the figures as JSON to this file");
    return cmd;
}
#endif

static CLI::App* addReferenceCommand(CLI::App& app, eval::ReferenceOptions& o, std::string& json) {
    auto* cmd = app.add_subcommand(
        "reference", "a cached reference with every type layer and its own error (two halves)");
    cmd->add_option("--scene", o.scene, "a .gltf/.glb scene")->required();
    cmd->add_option("--out", o.out, "also copy the reference here");
    cmd->add_option("--cache", o.cacheDir,
                    "cache folder (default $PARTITA_REFERENCE_CACHE, else <build>/references)");
    cmd->add_flag("--no-cache", o.noCache, "neither read nor write the cache (needs --out)");
    cmd->add_flag("--force", o.force, "render even when cached, replacing the cached file");
    cmd->add_flag("--quiet", o.quiet, "no progress bar");
    // The reference keeps every type (1024 is the film's limit) and defaults to BDPT.
    o.render.algorithm = "bdpt";
    o.render.settings.maxTypeLayers = 1024;
    addRenderOptions(*cmd, o.render);
    cmd->get_option("--algorithm")->description("the reference's algorithm")->capture_default_str();
    cmd->add_option("--json", json, "also write the figures as JSON to this file");
    return cmd;
}

static CLI::App* addQualityCommand(CLI::App& app, eval::QualityOptions& o, std::string& json) {
    auto* cmd = app.add_subcommand(
        "quality", "RMSE/relMSE against a reference per algorithm over seeds, time, memory");
    cmd->add_option("--scene", o.scene, "a .gltf/.glb scene")->required();
    cmd->add_option("--reference", o.reference, "the reference EXR (partita-eval reference)")
        ->required();
    cmd->add_option("--algorithms", o.algorithms, "comma-separated, e.g. pt,bdpt")
        ->required()
        ->delimiter(',');
    cmd->add_option("--seeds", o.seeds, "independent renders per algorithm (seeds --seed, +1 ...)")
        ->capture_default_str();
    cmd->add_flag("--equal-time", o.equalTime,
                  "every algorithm after the first gets the first's mean wall time");
    cmd->add_option("--table-layers", o.tableLayers, "type layers in the printed table")
        ->capture_default_str();
    cmd->add_flag("--quiet", o.quiet, "no progress bar");
    // The renders keep the film's default of 32 type layers, the largest by energy: each is
    // compared with the reference's layer of that type, and the resolved layers (width x height
    // x 12 bytes each) would otherwise dominate the measured memory. --layers 1024 compares all.
    addRenderOptions(*cmd, o.render);
    cmd->remove_option(cmd->get_option("--algorithm"));  // --algorithms instead
    for (const char* size : {"--width", "--height"})     // unless given, the reference's size
        cmd->get_option(size)->default_str("the reference's");
    cmd->add_option("--json", json, "also write the figures as JSON to this file");
    return cmd;
}

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
    eval::ReferenceOptions ro;
    CLI::App* reference = addReferenceCommand(app, ro, jsonPath);
    eval::QualityOptions qo;
    CLI::App* quality = addQualityCommand(app, qo, jsonPath);
#ifdef PARTITA_EVAL_SERVICE
    eval::ServiceOptions so;
    CLI::App* service = addServiceCommand(app, so, jsonPath);
#endif
    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "partita-eval: %s (see --help)\n", e.what());
        return 2;
    }
    try {
        // Every output path is checked before anything renders (a reference takes minutes).
        if (!jsonPath.empty()) requireOutputFolder(jsonPath);
        if (!ro.out.empty()) requireOutputFolder(ro.out);
        nlohmann::json out;
        if (*throughput) out = eval::runThroughput(tp);
        if (*reference) out = eval::runReference(ro);
        if (*quality) {
            qo.sizeGiven = quality->count("--width") + quality->count("--height") > 0;
            out = eval::runQuality(qo);
        }
#ifdef PARTITA_EVAL_SERVICE
        if (*service) out = eval::runServiceBench(so);
#endif
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
