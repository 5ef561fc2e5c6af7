// The private daemon: with no --server, the CLI runs its own partitad for the duration of one
// command, so that `partita render scene.gltf` is all it takes to render.
//
// It is started as `partitad --listen 127.0.0.1:0 --port-file F --store T/store --scene-root R
// [--threads N]` in a fresh temporary folder T (mkdtemp under $TMPDIR or /tmp), in its own
// process group (a Ctrl-C reaches the CLI only, which then cancels and stops in order) and with
// a parent-death signal (it never outlives a killed CLI). Ready means: the port file names the
// port and the standard health check answers SERVING. Stopping sends SIGTERM, waits up to 10 s
// (then SIGKILL) and removes T. partitad's own output goes to T/partitad.log; when it fails to
// start, its last line is the error.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>

namespace partita::cli {

class PrivateDaemon {
  public:
    struct Options {
        int threads = 0;  // 0: partitad's default
        double startTimeoutSeconds = 30;
    };

    /// Starts partitad and waits until it serves; throws CliError on failure (and cleans up).
    explicit PrivateDaemon(const Options& options);
    ~PrivateDaemon();
    PrivateDaemon(const PrivateDaemon&) = delete;
    PrivateDaemon& operator=(const PrivateDaemon&) = delete;

    /// "127.0.0.1:PORT".
    const std::string& address() const { return address_; }
    /// Stops the daemon and removes its folder; idempotent.
    void stop();

  private:
    void start(const Options& options);
    std::string lastLogLine() const;

    pid_t pid_ = -1;
    std::filesystem::path dir_;
    std::string address_;
};

}  // namespace partita::cli
