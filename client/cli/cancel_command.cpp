// partita --server HOST:PORT cancel JOB
// Prints "job ID: <state>" (cancelled, or the state it had already ended in).
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "cli/job_format.h"

namespace partita::cli {

namespace {

int runCancel(const GlobalOptions& global, const std::string& jobId) {
    requireServer(global, "cancel");
    Session session(global);
    partita::v1::CancelJobRequest request;
    request.set_job_id(jobId);
    partita::v1::Job job = session.connection().call(&Connection::Stub::CancelJob, request,
                                                     "cancel job " + jobId);
    std::printf("job %s: %s\n", jobId.c_str(), stateName(job.state()).c_str());
    return 0;
}

}  // namespace

Command addCancelCommand(CLI::App& app, const GlobalOptions& global) {
    auto job = std::make_shared<std::string>();
    CLI::App* sub = app.add_subcommand("cancel", "cancel a queued or running job");
    sub->add_option("job", *job, "job id")->required();
    return {sub, [&global, job] { return runCancel(global, *job); }};
}

}  // namespace partita::cli
