// Sends an uploaded scene ahead of its jobs (UploadScene): the files stream in 1 MiB pieces, so
// neither side holds more than a piece in flight, and the jobs name the upload by its id (a
// sweep's jobs share one upload). A server that is receiving as many uploads as it takes
// (--max-upload-streams) is waited for, saying so once.
#pragma once

#include "cli/connection.h"
#include "cli/proto.h"

namespace partita::cli {

/// Streams `source` when it holds an upload (.glb, or .gltf with resources) and replaces it
/// with the upload's id; a named scene is left as it is. Throws CliError on a refusal.
void uploadScene(Connection& conn, partita::v1::SceneSource& source);

}  // namespace partita::cli
