// partita --server HOST:PORT watch JOB [--previews DIR]
// Follows a job until it ends; exits 0 when it is done, 1 when it failed or was cancelled.
// Ctrl-C stops watching and leaves the job running.
#include <filesystem>
#include <memory>

#include "cli/commands.h"
#include "cli/job_format.h"
#include "cli/watch.h"
#include "frontend/progress_bar.h"

namespace partita::cli {

namespace fs = std::filesystem;

namespace {

struct WatchArgs {
    std::string job, previews;
};

int runWatch(const GlobalOptions& global, const WatchArgs& a) {
    requireServer(global, "watch");
    WatchOptions watch;
    watch.progressBar = !global.quiet;
    // State lines only on a terminal: in logs and scripts, a failure stays one line.
    watch.announceStates = !global.quiet && ProgressBar::stderrIsTerminal();
    watch.announceDone = !global.quiet;
    if (!a.previews.empty()) {
        std::error_code ec;
        fs::create_directories(a.previews, ec);
        if (!fs::is_directory(a.previews, ec))
            throw CliError("cannot create the previews folder '" + a.previews + "'");
        watch.previewsDir = a.previews;
    }
    Session session(global);
    partita::v1::Job job;
    try {
        job = followJob(session.connection(), a.job, watch);
    } catch (const CliError& e) {
        if (e.exitCode() != 130) throw;
        throw CliError("interrupted; job " + a.job + " keeps running", "", 130);
    }
    requireDone(job);
    return 0;
}

}  // namespace

Command addWatchCommand(CLI::App& app, const GlobalOptions& global) {
    auto args = std::make_shared<WatchArgs>();
    CLI::App* sub = app.add_subcommand("watch", "follow a job's progress until it ends");
    sub->add_option("job", args->job, "job id")->required();
    sub->add_option("--previews", args->previews,
                    "folder for preview PNGs, one per layer, replaced as frames arrive");
    return {sub, [&global, args] { return runWatch(global, *args); }};
}

}  // namespace partita::cli
