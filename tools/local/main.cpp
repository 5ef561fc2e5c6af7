// partita-local: the core without the service. Renders a glTF scene in-process:
//   partita-local render SCENE --spp N --out x.exr [--png x.png] [render options]
//   partita-local info SCENE
// and runs one job as shards (shard_commands.h):
//   partita-local plan SCENE --shards N --out PLAN [render options]
//   partita-local render --plan PLAN [--shard I] --out SHARD
//   partita-local merge --plan PLAN SHARD... --out FILE.exr
// Bad input prints one line on stderr and exits non-zero.
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>

#include "file_io.h"
#include "frontend/progress_bar.h"
#include "frontend/render_options.h"
#include "gltf/gltf_loader.h"
#include "image_io.h"
#include "local_run.h"
#include "render_scene.h"
#include "renderer.h"
#include "shard_commands.h"
#include "thread_pool.h"

namespace fs = std::filesystem;
using namespace partita;

namespace {

std::atomic<bool> gCancel{false};
void onSignal(int) { gCancel.store(true); }

int renderCommand(const std::string& scenePath, RenderOptions& options, const std::string& outPath,
                  std::string pngPath, bool quiet) {
    if (std::string err = finalizeRenderOptions(options); !err.empty())
        throw std::invalid_argument(err);
    if (pngPath.empty()) pngPath = fs::path(outPath).replace_extension(".png").string();
    requireOutputFolder(outPath);
    requireOutputFolder(pngPath);
    RenderScene scene = loadLocalScene(scenePath, options.settings.environment);
    ThreadPool pool(options.threads);
    ProgressBar bar(!quiet && ProgressBar::stderrIsTerminal());
    BarObserver observer(bar, quiet);
    std::signal(SIGINT, onSignal);
    RenderResult result;
    try {
        result = runRender(scene, options.algorithm, options.settings, pool, gCancel, observer);
    } catch (const RenderCancelled&) {
        bar.finish();
        throw std::runtime_error("interrupted; nothing written");
    }
    bar.finish();
    writeExr(outPath, result.image,
             describeRender(options.algorithm, options.settings, result.stats));
    writePng(pngPath, result.image.combined, autoExposure(result.image.combined));
    if (!quiet) {
        std::fprintf(stderr, "wrote %s (%zu type layers) and %s in %s, %s rays/s\n",
                     outPath.c_str(), result.image.layers.size(), pngPath.c_str(),
                     humanDuration(result.stats.values["seconds"]).c_str(),
                     humanCount(result.stats.values["rays_per_second"]).c_str());
    }
    return 0;
}

int infoCommand(const std::string& scenePath) {
    SceneData data = loadGltfFile(scenePath);
    size_t triangles = 0;
    for (const auto& m : data.meshes) triangles += m.triangleCount();
    std::printf("meshes %zu, triangles %zu, materials %zu, textures %zu, punctual lights %zu\n",
                data.meshes.size(), triangles, data.materials.size(), data.textures.size(),
                data.lights.size());
    for (const auto& c : data.cameras)
        std::printf("camera '%s' (%s)\n", c.name.c_str(),
                    c.type == CameraDesc::Type::Perspective ? "perspective" : "orthographic");
    for (const auto& w : data.warnings) std::printf("warning: %s\n", w.c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"partita-local: render glTF scenes in-process with the Partita core"};
    app.require_subcommand(1);
    std::string scenePath, outPath = "out.exr", pngPath;
    bool quiet = false;
    RenderOptions options;
    ShardCommand shard;
    auto* render = app.add_subcommand(
        "render", "render a scene to a multi-layer EXR and a PNG preview, or one shard of a plan");
    render->add_option("scene", scenePath, "a .gltf or .glb file (not with --plan)");
    render
        ->add_option("--out", outPath,
                     "output EXR (combined + one layer per path type); with --plan the shard")
        ->capture_default_str();
    render->add_option("--png", pngPath, "PNG preview (default: the EXR name with .png)");
    render->add_flag("--quiet", quiet, "no progress bar");
    render->add_option("--plan", shard.plan, "render one shard of this plan (partita-local plan)");
    render->add_option("--shard", shard.shard,
                       "the shard index (default: $SLURM_ARRAY_TASK_ID or $JOB_COMPLETION_INDEX)");
    addRenderOptions(*render, options, algorithmInArguments(argc, argv));

    PlanCommand plan;
    auto* planApp = app.add_subcommand(
        "plan", "plan a job as N shards: runs its start-up once and writes the plan file");
    planApp->add_option("scene", plan.scene, "a .gltf or .glb file")->required();
    planApp->add_option("--shards", plan.shards, "number of shards")->required();
    planApp->add_option("--out", plan.out, "the plan file")->required();
    planApp->add_flag("--quiet", quiet, "no progress bar");
    addRenderOptions(*planApp, options, algorithmInArguments(argc, argv));

    MergeCommand merge;
    auto* mergeApp = app.add_subcommand(
        "merge", "merge the shards of a plan into the job's EXR, bit-identical to one process");
    mergeApp->add_option("shards", merge.shards, "shard files, in any order")->required();
    mergeApp->add_option("--plan", merge.plan, "the plan the shards were rendered from")
        ->required();
    mergeApp->add_option("--out", merge.out, "output EXR")->required();
    mergeApp->add_option("--png", merge.png, "PNG preview (default: the EXR name with .png)");
    mergeApp->add_flag("--allow-partial", merge.allowPartial,
                       "write what the given shards hold even when some are missing");
    mergeApp->add_flag("--quiet", quiet, "no messages");

    auto* info = app.add_subcommand("info", "print what a scene contains");
    info->add_option("scene", scenePath, "a .gltf or .glb file")->required();
    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "partita-local: %s (see --help)\n", e.what());
        return 2;
    }
    spdlog::set_level(quiet ? spdlog::level::warn : spdlog::level::info);
    try {
        if (*render && !shard.plan.empty()) {
            if (!scenePath.empty())
                throw std::invalid_argument(
                    "give a scene or --plan, not both (the plan names its scene)");
            shard.out = outPath;
            shard.threads = options.threads;
            return runShardCommand(shard, quiet);
        }
        if (*render) {
            if (scenePath.empty()) throw std::invalid_argument("render needs a scene (or --plan)");
            return renderCommand(scenePath, options, outPath, pngPath, quiet);
        }
        if (*planApp) return runPlanCommand(plan, options, quiet);
        if (*mergeApp) return runMergeCommand(merge, quiet);
        return infoCommand(scenePath);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "partita-local: error: %s\n", e.what());
        return 1;
    }
}
