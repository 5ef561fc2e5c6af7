// Where the CLI finds what its private daemon needs.
//
// partitad, first match wins:
//   1. $PARTITA_PARTITAD (an error if set but not an executable file)
//   2. <dir of partita>/../server/partitad   (a build tree: build/client/partita)
//   3. <dir of partita>/partitad             (installed side by side, e.g. /usr/local/bin)
//   4. partitad on $PATH
// The scene root, first match wins:
//   1. $PARTITA_SCENE_ROOT (an error if set but not a folder)
//   2. <dir of partita>/../../scenes         (build tree inside the repository)
//   3. <dir of partita>/../share/partita/scenes  (installed)
//   4. the scenes/ folder of the source tree the binary was built from
//   otherwise none: the private daemon gets an empty scene root and only uploads work.
#pragma once

#include <filesystem>

namespace partita::cli {

/// Throws CliError when partitad cannot be found.
std::filesystem::path findPartitad();

/// Empty when there is none.
std::filesystem::path findSceneRoot();

}  // namespace partita::cli
