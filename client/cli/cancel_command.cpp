// partita --server HOST:PORT cancel JOB
// Prints "job ID: <state>": cancelled, or the state it had already ended in. A running job
// stops at the render's next cancellation point, so the command waits up to 10 s for the final
// state ("cancelling" if it has not arrived by then).
#include <chrono>
#include <cstdio>
#include <memory>
#include <thread>

#include "cli/commands.h"
#include "cli/job_format.h"

namespace partita::cli {

namespace {

int runCancel(const GlobalOptions& global, const std::string& jobId) {
    requireServer(global, "cancel");
    Session session(global);
    partita::v1::CancelJobRequest request;
    request.set_job_id(jobId);
    partita::v1::Job job =
        session.connection().call(&Connection::Stub::CancelJob, request, "cancel job " + jobId);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!isTerminal(job.state()) && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        partita::v1::GetJobRequest get;
        get.set_job_id(jobId);
        job = session.connection().call(&Connection::Stub::GetJob, get, "look up job " + jobId);
    }
    std::printf("job %s: %s\n", jobId.c_str(),
                isTerminal(job.state()) ? stateName(job.state()).c_str() : "cancelling");
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
