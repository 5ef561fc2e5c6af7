#include "cli/watch.h"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>

#include "cli/file_util.h"
#include "cli/job_format.h"
#include "cli/signals.h"
#include "frontend/progress_bar.h"

namespace partita::cli {

namespace {

int64_t nowMs() {
    return std::chrono::duration_cast<std::chrono::milliseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

// After the final state, the server closes the stream; should it not, stop waiting after this.
constexpr int64_t kAfterTerminalGraceMs = 5000;
constexpr int kMaxReconnects = 100;

}  // namespace

void writePreviewFrame(const std::filesystem::path& dir, const partita::v1::PreviewFrame& frame) {
    for (const auto& layer : frame.layers())
        if (!layer.png().empty())
            writeFileAtomically(dir / (safeFileName(layer.name()) + ".png"), layer.png());
}

partita::v1::Job followJob(Connection& connection, const std::string& jobId,
                           const WatchOptions& options) {
    ProgressBar bar(ProgressBar::stderrIsTerminal());
    partita::v1::Job last;
    bool haveState = false;
    auto announce = [&](const partita::v1::Job& job) {
        if (!options.announceStates) return;
        if (haveState && job.state() == last.state()) return;
        if (options.progressBar) bar.finish();
        std::string line = "job " + jobId + ": " + stateName(job.state());
        if (job.state() == partita::v1::JOB_STATE_FAILED && !job.error().empty())
            line += " (" + oneLine(job.error()) + ")";
        std::fprintf(stderr, "%s\n", line.c_str());
    };

    // Without a terminal no state lines are printed (a failure stays one line), but a successful
    // end is still said, so that a log shows how the job ended.
    auto announceEnd = [&](const partita::v1::Job& job) {
        if (options.announceStates || !options.announceDone) return;
        if (job.state() != partita::v1::JOB_STATE_DONE) return;
        std::fprintf(stderr, "job %s: done in %s\n", jobId.c_str(),
                     humanDuration(jobSeconds(job)).c_str());
    };

    for (int attempt = 0;; ++attempt) {
        grpc::ClientContext context;
        connection.prepare(context);
        partita::v1::WatchJobRequest request;
        request.set_job_id(jobId);
        request.set_previews(!options.previewsDir.empty());
        auto reader = connection.stub().WatchJob(&context, request);

        std::atomic<bool> finished{false};
        std::atomic<int64_t> terminalAtMs{0};
        std::thread guard([&] {
            while (!finished.load()) {
                const int64_t t = terminalAtMs.load();
                if (interrupted() || (t > 0 && nowMs() - t > kAfterTerminalGraceMs)) {
                    context.TryCancel();
                    return;
                }
                std::this_thread::sleep_for(std::chrono::milliseconds(50));
            }
        });

        partita::v1::JobEvent event;
        try {
            while (reader->Read(&event)) {
                switch (event.event_case()) {
                    case partita::v1::JobEvent::kState:
                        announce(event.state());
                        last = event.state();
                        haveState = true;
                        if (isTerminal(last.state())) terminalAtMs = nowMs();
                        break;
                    case partita::v1::JobEvent::kProgress:
                        if (options.progressBar && !isTerminal(last.state()))
                            bar.update(toRenderProgress(event.progress()));
                        break;
                    case partita::v1::JobEvent::kPreview:
                        if (!options.previewsDir.empty())
                            writePreviewFrame(options.previewsDir, event.preview());
                        break;
                    default:
                        break;
                }
            }
        } catch (...) {
            finished = true;
            context.TryCancel();
            guard.join();
            throw;
        }
        finished = true;
        guard.join();
        grpc::Status status = reader->Finish();
        if (options.progressBar) bar.finish();
        if (interrupted()) throw CliError("interrupted", "", 130);
        if (haveState && isTerminal(last.state())) {
            announceEnd(last);
            return last;
        }
        if (!status.ok()) connection.fail(status, "watch job " + jobId);

        // The stream ended without a final state: look the job up, and watch again if needed.
        partita::v1::GetJobRequest get;
        get.set_job_id(jobId);
        partita::v1::Job job =
            connection.call(&Connection::Stub::GetJob, get, "look up job " + jobId);
        if (isTerminal(job.state())) {
            announce(job);
            announceEnd(job);
            return job;
        }
        if (attempt >= kMaxReconnects)
            throw CliError("watch job " + jobId + ": the server keeps ending the stream early");
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
}

void cancelJobQuietly(Connection& connection, const std::string& jobId) {
    grpc::ClientContext context;
    connection.prepare(context, 10);
    partita::v1::CancelJobRequest request;
    request.set_job_id(jobId);
    partita::v1::Job job;
    connection.stub().CancelJob(&context, request, &job);
}

partita::v1::Job cancelAndWait(Connection& connection, const std::string& jobId, double seconds) {
    cancelJobQuietly(connection, jobId);
    partita::v1::Job job;
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::milliseconds(int64_t(seconds * 1000));
    do {
        grpc::ClientContext context;
        connection.prepare(context, 5);
        partita::v1::GetJobRequest get;
        get.set_job_id(jobId);
        if (!connection.stub().GetJob(&context, get, &job).ok()) break;
        if (isTerminal(job.state())) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    } while (std::chrono::steady_clock::now() < deadline);
    return job;
}

void requireDone(const partita::v1::Job& job) {
    switch (job.state()) {
        case partita::v1::JOB_STATE_DONE:
            return;
        case partita::v1::JOB_STATE_FAILED:
            throw CliError(
                "job " + job.id() + " failed: " +
                (job.error().empty() ? std::string("no reason given") : oneLine(job.error())));
        case partita::v1::JOB_STATE_CANCELLED:
            throw CliError("job " + job.id() + " was cancelled");
        default:
            throw CliError("job " + job.id() + " is " + stateName(job.state()) + ", not done");
    }
}

}  // namespace partita::cli
