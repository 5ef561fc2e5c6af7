// partita [--server HOST:PORT] sweep SCENE --sweep NAME=V1,V2,... [--sweep NAME=V1,V2,...]
//         [render flags] [--reference REF.exr] [--out-dir DIR]
// Renders the grid over one or two job parameters (sweep_axis.h): submits every job, waits for
// all, downloads each result as DIR/<name1>=<v1>_<name2>=<v2>.exr (+ .png, .json), and prints
// a table (also written to DIR/sweep.csv) with the parameters, RMSE and relMSE of the combined
// image against --reference (core/image_metrics.h) and the render seconds.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>

#include "cli/commands.h"
#include "cli/file_util.h"
#include "cli/image_files.h"
#include "cli/job_format.h"
#include "cli/job_spec.h"
#include "cli/results.h"
#include "cli/scene_source.h"
#include "cli/scene_upload.h"
#include "cli/sweep_axis.h"
#include "cli/table.h"
#include "cli/watch.h"
#include "params/job_parameters.h"

namespace partita::cli {

namespace fs = std::filesystem;

namespace {

struct SweepArgs {
    std::string scene, reference, outDir;
    std::vector<std::string> sweeps;
    JobFlags flags;
};

struct Cell {
    std::vector<std::string> values;  // one per axis
    partita::v1::JobSpec spec;
    std::string id, file;
    partita::v1::Job job;
    double rmse = std::numeric_limits<double>::quiet_NaN(), relMse = rmse, seconds = rmse;
};

std::vector<SweepAxis> parseAxes(const std::vector<std::string>& sweeps,
                                 const std::string& algorithm) {
    if (sweeps.empty())
        throw CliError(
            "sweep needs --sweep NAME=V1,V2,... (NAME spp, mpp, seconds or a parameter of the "
            "algorithm)");
    if (sweeps.size() > 2) throw CliError("sweep takes at most two --sweep axes");
    std::vector<SweepAxis> axes;
    for (const auto& s : sweeps) axes.push_back(parseSweepAxis(s, algorithm));
    if (axes.size() == 2 && axes[0].name == axes[1].name)
        throw CliError("both --sweep axes name '" + axes[0].name + "'");
    int budgets = 0;
    for (const auto& a : axes) budgets += a.name == "spp" || a.name == "mpp" || a.name == "seconds";
    if (budgets > 1) throw CliError("spp, mpp and seconds all set the budget: sweep one of them");
    return axes;
}

/// Refuses a reference of another size than a sweep point renders (unset sizes take the
/// server's defaults, RenderSettings'), before anything is submitted.
void checkReferenceSize(const partita::v1::JobSpec& spec, const LayeredImage& reference,
                        const std::string& point, const std::string& file) {
    std::string error;
    const RenderSettings s = settingsOfSpec(spec, error);
    int w = s.width, h = s.height;
    if (w == reference.combined.width && h == reference.combined.height) return;
    throw CliError("sweep point " + point + " renders " + std::to_string(w) + "x" +
                   std::to_string(h) + " but the reference " + file + " is " +
                   std::to_string(reference.combined.width) + "x" +
                   std::to_string(reference.combined.height) +
                   ": give --width/--height of the reference, or another reference");
}

/// Refuses an axis over a parameter the algorithm ignores (`reads`: the budgets and parameters
/// it takes, in the CLI's spelling): every image would be the same.
void checkAxesMatter(const std::vector<std::string>& reads, const std::string& algorithm,
                     const std::vector<SweepAxis>& axes) {
    if (reads.empty()) return;  // the server does not say
    std::string list;
    for (const auto& p : reads) list += (list.empty() ? "" : ", ") + p;
    for (const auto& axis : axes)
        if (std::find(reads.begin(), reads.end(), axis.name) == reads.end())
            throw CliError("--sweep " + axis.name + ": algorithm '" + algorithm + "' ignores " +
                               axis.name + ", so every image would be the same (" + algorithm +
                               " reads " + list + ")",
                           "INVALID_ARGUMENT");
}

/// What `algorithm` takes as this build declares it (the server's own algorithms: nothing).
std::vector<std::string> localParameters(const std::string& algorithm) {
    registerBuiltinAlgorithms();
    const auto* entry = AlgorithmRegistry::instance().find(algorithm);
    if (!entry) return {};
    std::vector<std::string> out;
    for (BudgetKind kind : entry->budgets()) out.push_back(budgetKindName(kind));
    for (const ParameterSpec& spec : jobParameterSpecs(*entry)) out.push_back(flagName(spec.name));
    return out;
}

int runSweep(CLI::App& sub, const GlobalOptions& global, SweepArgs& a) {
    const std::vector<SweepAxis> axes = parseAxes(a.sweeps, a.flags.render.algorithm);
    checkAxesMatter(localParameters(a.flags.render.algorithm), a.flags.render.algorithm, axes);
    const SceneArgument scene = classifyScene(a.scene);
    partita::v1::JobSpec base = makeJobSpec(sub, a.flags);
    *base.mutable_scene() = loadSceneSource(scene);
    if (scene.isFile) base.set_scene_file(fs::path(scene.text).filename().string());
    addEnvironmentImage(base, a.flags.render.settings.environment.file);
    if (base.label().empty()) base.set_label("sweep:" + sceneStem(scene));

    LayeredImage reference;
    if (!a.reference.empty()) reference = readResultExr(a.reference);
    const fs::path outDir =
        a.outDir.empty() ? fs::path("sweep-" + safeFileName(sceneStem(scene))) : fs::path(a.outDir);
    std::error_code ec;
    fs::create_directories(outDir, ec);
    if (!fs::is_directory(outDir, ec))
        throw CliError("cannot create the output folder '" + outDir.string() + "'");

    // The grid, row-major: the first axis varies slowest.
    std::vector<Cell> cells;
    const size_t n0 = axes[0].values.size(), n1 = axes.size() > 1 ? axes[1].values.size() : 1;
    for (size_t i = 0; i < n0; ++i)
        for (size_t j = 0; j < n1; ++j) {
            Cell c;
            c.spec = base;
            std::string name;
            for (size_t k = 0; k < axes.size(); ++k) {
                const std::string& v = axes[k].values[k == 0 ? i : j];
                c.values.push_back(v);
                applySweepValue(c.spec, axes[k].name, v);
                name += (name.empty() ? "" : "_") + axes[k].name + "=" + v;
            }
            if (std::string err = validateJobSpec(c.spec); !err.empty())
                throw CliError("sweep point " + name + ": " + err);
            if (!a.reference.empty()) checkReferenceSize(c.spec, reference, name, a.reference);
            c.file = (outDir / (safeFileName(name) + ".exr")).string();
            cells.push_back(std::move(c));
        }

    Session session(global, a.flags.render.threads);
    Connection& conn = session.connection();
    session.checkAlgorithm(base.algorithm());
    checkAxesMatter(session.algorithmParameters(base.algorithm()), base.algorithm(), axes);
    for (const auto& c : cells) session.checkLimits(c.spec);
    // One upload for every point of the sweep.
    uploadScene(conn, *base.mutable_scene());
    for (auto& c : cells) *c.spec.mutable_scene() = base.scene();
    auto cancelRest = [&] {
        for (auto& c : cells)
            if (!c.id.empty() && !isTerminal(c.job.state())) cancelJobQuietly(conn, c.id);
        for (auto& c : cells)
            if (!c.id.empty() && !isTerminal(c.job.state())) cancelAndWait(conn, c.id, 10);
    };
    try {
        for (auto& c : cells) {
            partita::v1::SubmitJobRequest request;
            *request.mutable_spec() = c.spec;
            c.id =
                conn.call(&Connection::Stub::SubmitJob, request, "submit sweep job", 300).job_id();
        }
        WatchOptions quiet;
        quiet.progressBar = quiet.announceStates = false;
        size_t finished = 0;
        for (auto& c : cells) {
            c.job = followJob(conn, c.id, quiet);
            ++finished;
            c.seconds = jobSeconds(c.job);
            if (!global.quiet) {
                std::string point;
                for (size_t k = 0; k < axes.size(); ++k)
                    point += std::string(k ? " " : "") + axes[k].name + "=" + c.values[k];
                std::fprintf(stderr, "[%zu/%zu] %s: %s (%s)\n", finished, cells.size(),
                             point.c_str(), stateName(c.job.state()).c_str(),
                             formatNumber(c.seconds).c_str());
            }
        }
    } catch (const CliError& e) {
        if (e.exitCode() == 130) {
            cancelRest();
            throw CliError("interrupted; the sweep's jobs were cancelled", "", 130);
        }
        throw;
    }

    std::vector<std::string> headers;
    for (const auto& axis : axes) headers.push_back(axis.name);
    if (!a.reference.empty()) headers.insert(headers.end(), {"rmse", "relmse"});
    headers.insert(headers.end(), {"seconds", "state", "file"});
    Table table(headers);
    size_t failed = 0;
    std::string firstError;
    for (auto& c : cells) {
        std::vector<std::string> row = c.values;
        if (c.job.state() == partita::v1::JOB_STATE_DONE) {
            downloadResults(conn, c.id, c.file);
            if (!a.reference.empty()) {
                // Sizes were checked before submitting; a mismatch here (a server with other
                // defaults) is an error too, as in `partita compare`.
                try {
                    ErrorMetrics m = imageError(readResultExr(c.file).combined, reference.combined);
                    c.rmse = m.rmse;
                    c.relMse = m.relMse;
                } catch (const CliError& e) {
                    throw CliError(c.file + ": " + e.what() + " (--reference " + a.reference + ")");
                }
            }
        } else {
            ++failed;
            if (firstError.empty())
                firstError = "job " + c.id + " " + stateName(c.job.state()) +
                             (c.job.error().empty() ? "" : ": " + oneLine(c.job.error()));
        }
        if (!a.reference.empty()) {
            row.push_back(formatNumber(c.rmse));
            row.push_back(formatNumber(c.relMse));
        }
        row.push_back(formatNumber(c.seconds));
        row.push_back(stateName(c.job.state()));
        row.push_back(c.job.state() == partita::v1::JOB_STATE_DONE ? c.file : "-");
        table.addRow(row);
    }
    writeFileAtomically(outDir / "sweep.csv", table.csv());
    table.print(stdout);
    if (failed)
        throw CliError(std::to_string(failed) + " of " + std::to_string(cells.size()) +
                       " sweep jobs did not finish (" + firstError + ")");
    return 0;
}

}  // namespace

Command addSweepCommand(CLI::App& app, const GlobalOptions& global) {
    auto args = std::make_shared<SweepArgs>();
    CLI::App* sub = app.add_subcommand("sweep", "render a grid over one or two job parameters");
    sub->add_option("scene", args->scene, "a .gltf/.glb file or a scene name")->required();
    sub->add_option("--sweep", args->sweeps,
                    "NAME=V1,V2,... (given once or twice); NAME: spp, mpp, seconds or a "
                    "parameter of the algorithm (see --help with --algorithm)")
        ->allow_extra_args(false)
        ->required();
    addJobOptions(*sub, args->flags, global.helpAlgorithm);
    sub->add_option("--reference", args->reference, "reference EXR for RMSE and relMSE");
    sub->add_option("--out-dir", args->outDir,
                    "folder for the results and sweep.csv (default: sweep-<scene>)");
    return {sub, [sub, &global, args] { return runSweep(*sub, global, *args); }};
}

}  // namespace partita::cli
