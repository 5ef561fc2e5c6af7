// Following a job: streams its events, draws the progress bar (rate and ETA), announces state
// changes and writes preview frames, until the job ends.
#pragma once

#include <filesystem>
#include <string>

#include "cli/connection.h"

namespace partita::cli {

struct WatchOptions {
    std::filesystem::path previewsDir;  // empty: no previews; else <dir>/<layer>.png, replaced
                                        // by each new frame
    bool progressBar = true;            // on stderr
    bool announceStates = true;         // "job ID: rendering" lines on stderr
    bool announceDone = false;          // "job ID: done" at the end even without announceStates
};

/// Returns the job in its final state (done, failed or cancelled). If the stream breaks off
/// before that, the job is looked up and watched again. Throws CliError on errors, and with
/// exit code 130 when interrupted (the job is left as it is).
partita::v1::Job followJob(Connection& connection, const std::string& jobId,
                           const WatchOptions& options);

/// Throws CliError unless the job is done: "job ID failed: <why>", "job ID was cancelled".
void requireDone(const partita::v1::Job& job);

/// Cancels a job, ignoring failures (used when the CLI is interrupted while it owns the job).
void cancelJobQuietly(Connection& connection, const std::string& jobId);

/// cancelJobQuietly, then waits up to `seconds` for the job to end; returns the job as last
/// seen (its state is not terminal when the wait ran out or the server could not be asked).
partita::v1::Job cancelAndWait(Connection& connection, const std::string& jobId, double seconds);

/// Writes each layer of a preview frame as <dir>/<layer>.png (atomically).
void writePreviewFrame(const std::filesystem::path& dir, const partita::v1::PreviewFrame& frame);

}  // namespace partita::cli
