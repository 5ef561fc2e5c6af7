// partita render SCENE [render flags] [--out FILE.exr] [--previews DIR] [--detach]
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli/commands.h"
#include "cli/file_util.h"
#include "cli/job_format.h"
#include "cli/job_spec.h"
#include "cli/results.h"
#include "cli/scene_source.h"
#include "cli/scene_upload.h"
#include "cli/watch.h"
#include "frontend/progress_bar.h"

namespace partita::cli {

namespace fs = std::filesystem;

namespace {

struct RenderArgs {
    std::string scene, out, previews;
    bool detach = false;
    JobFlags flags;
};

int runRender(CLI::App& sub, const GlobalOptions& global, RenderArgs& a) {
    const SceneArgument scene = classifyScene(a.scene);
    if (a.detach && global.server.server.empty())
        throw CliError(
            "--detach needs --server HOST:PORT (a private daemon stops when the "
            "command returns)");
    partita::v1::JobSpec spec = makeJobSpec(sub, a.flags);
    *spec.mutable_scene() = loadSceneSource(scene);  // reads and checks files before anything runs
    if (scene.isFile) spec.set_scene_file(fs::path(scene.text).filename().string());
    addEnvironmentImage(spec, a.flags.render.settings.environment.file);

    const fs::path out =
        a.out.empty() ? fs::path(safeFileName(sceneStem(scene)) + ".exr") : fs::path(a.out);
    if (!a.detach) requireOutputFolder(out);
    WatchOptions watch;
    watch.progressBar = !global.quiet;
    // State lines only on a terminal: in logs and scripts, a failure stays one line.
    watch.announceStates = !global.quiet && ProgressBar::stderrIsTerminal();
    watch.announceDone = !global.quiet;
    if (!a.previews.empty() && !a.detach) {
        std::error_code ec;
        fs::create_directories(a.previews, ec);
        if (!fs::is_directory(a.previews, ec))
            throw CliError("cannot create the previews folder '" + a.previews + "'");
        watch.previewsDir = a.previews;
    }

    Session session(global, a.flags.render.threads);
    Connection& conn = session.connection();
    session.checkAlgorithm(spec.algorithm());
    session.checkLimits(spec);
    uploadScene(conn, *spec.mutable_scene());
    partita::v1::SubmitJobRequest request;
    *request.mutable_spec() = spec;
    const std::string id =
        conn.call(&Connection::Stub::SubmitJob, request, "submit job", 300).job_id();
    if (a.detach) {
        std::printf("%s\n", id.c_str());
        std::fflush(stdout);
        return 0;
    }

    partita::v1::Job job;
    try {
        job = followJob(conn, id, watch);
    } catch (const CliError& e) {
        if (e.exitCode() != 130) throw;
        // The job is this command's own: cancel it and wait (bounded) until it has stopped, so
        // that `jobs` never shows it still rendering.
        partita::v1::Job end = cancelAndWait(conn, id, 10);
        throw CliError("interrupted; job " + id +
                           (isTerminal(end.state()) ? " cancelled" : " is being cancelled"),
                       "", 130);
    }
    requireDone(job);
    ResultFiles files = downloadResults(conn, id, out);
    if (!global.quiet)
        std::fprintf(stderr, "wrote %s, %s and %s (rendered in %s)\n", files.exr.c_str(),
                     files.png.c_str(), files.json.c_str(), humanDuration(jobSeconds(job)).c_str());
    return 0;
}

}  // namespace

Command addRenderCommand(CLI::App& app, const GlobalOptions& global) {
    auto args = std::make_shared<RenderArgs>();
    CLI::App* sub = app.add_subcommand("render", "render a scene and download its results");
    sub->add_option("scene", args->scene,
                    "a .gltf/.glb file (uploaded with its resources) or a scene name of the "
                    "server's scene root")
        ->required();
    addJobOptions(*sub, args->flags, global.helpAlgorithm);
    sub->add_option("--out", args->out,
                    "result EXR; the PNG and the JSON metadata go beside it (default: "
                    "<scene>.exr)");
    sub->add_option("--previews", args->previews,
                    "folder for preview PNGs, one per layer, replaced as frames arrive");
    sub->add_flag("--detach", args->detach, "print the job id and return at once");
    return {sub, [sub, &global, args] { return runRender(*sub, global, *args); }};
}

}  // namespace partita::cli
