// Runs a program (no shell) and collects its exit status and output: how partitad talks to a
// batch system (sbatch, squeue, scancel).
#pragma once

#include <string>
#include <vector>

namespace partita::server {

struct ProcessResult {
    int exitCode = -1;  // the program's exit status; -1 when it could not start or was killed
    std::string out, err;
    bool ok() const { return exitCode == 0; }
    /// "<argv[0]>: <first line of stderr>" (or of stdout, or the exit status), for messages.
    std::string describe(const std::string& program) const;
};

/// Runs argv[0] (looked up in PATH) with argv, stdin closed, stdout and stderr captured (at
/// most 1 MiB each); kills it after `timeoutSeconds`.
ProcessResult runProcess(const std::vector<std::string>& argv, double timeoutSeconds = 60);

}  // namespace partita::server
