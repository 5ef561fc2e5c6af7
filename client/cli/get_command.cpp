// partita --server HOST:PORT get JOB [--out FILE.exr]
// Downloads a finished job's EXR, and the PNG and JSON metadata beside it.
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "cli/file_util.h"
#include "cli/job_format.h"
#include "cli/results.h"

namespace partita::cli {

namespace fs = std::filesystem;

namespace {

struct GetArgs {
    std::string job, out;
};

int runGet(const GlobalOptions& global, const GetArgs& a) {
    requireServer(global, "get");
    const fs::path out = a.out.empty() ? fs::path(safeFileName(a.job) + ".exr") : fs::path(a.out);
    requireOutputFolder(out);
    Session session(global);
    Connection& conn = session.connection();
    partita::v1::GetJobRequest request;
    request.set_job_id(a.job);
    partita::v1::Job job = conn.call(&Connection::Stub::GetJob, request, "look up job " + a.job);
    if (job.state() != partita::v1::JOB_STATE_DONE)
        throw CliError(
            "job " + a.job + " is " + stateName(job.state()) + "; results exist once it is done",
            "FAILED_PRECONDITION");
    ResultFiles files = downloadResults(conn, a.job, out);
    if (!global.quiet)
        std::fprintf(stderr, "wrote %s, %s and %s\n", files.exr.c_str(), files.png.c_str(),
                     files.json.c_str());
    return 0;
}

}  // namespace

Command addGetCommand(CLI::App& app, const GlobalOptions& global) {
    auto args = std::make_shared<GetArgs>();
    CLI::App* sub = app.add_subcommand("get", "download a finished job's results");
    sub->add_option("job", args->job, "job id")->required();
    sub->add_option("--out", args->out,
                    "result EXR; the PNG and the JSON metadata go beside it (default: <job>.exr)");
    return {sub, [&global, args] { return runGet(global, *args); }};
}

}  // namespace partita::cli
