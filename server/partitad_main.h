// partitad's whole life: options, start-up, serving until SIGTERM/SIGINT, shutdown. main.cpp
// calls it; a test daemon that registers one more algorithm first calls it too.
//
// SIGTERM/SIGINT: stop taking jobs, cancel the running ones (they are re-queued in the store and
// run again after a restart), end the streams, flush the store, exit 0.
#pragma once

namespace partita::server {

/// Runs the daemon with the command line `argv`; returns the process's exit status.
int partitadMain(int argc, char** argv);

}  // namespace partita::server
