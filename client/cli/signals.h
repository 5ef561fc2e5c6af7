// Ctrl-C and SIGTERM: the CLI notes them and winds down in order (cancels the job it submitted
// when it was rendering, stops its private daemon, removes temporary files).
#pragma once

namespace partita::cli {

/// Installs handlers for SIGINT and SIGTERM that only set a flag.
void installInterruptHandler();
bool interrupted();

}  // namespace partita::cli
