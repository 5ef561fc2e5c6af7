// A JobSpec checked against the contract and this server's limits, and mapped to the core's
// RenderSettings. Codes (DESIGN.md): a malformed request is INVALID_ARGUMENT (unknown enum value,
// unknown algorithm, parameter out of range); asking for more than the server allows is
// RESOURCE_EXHAUSTED (resolution, budget, upload size). Whether a named scene exists is checked
// by the caller (scene_source.h), not here.
#pragma once

#include <grpcpp/support/status.h>

#include <functional>
#include <set>
#include <string>
#include <vector>

#include "image_io.h"
#include "proto.h"
#include "render_settings.h"
#include "service_limits.h"

namespace partita::server {

class SceneSource;

struct ValidatedSpec {
    std::string algorithm;
    RenderSettings settings;
    /// The environment image's header, when the job names one that could be read at submission
    /// (checkEnvironmentImage): what admission counts for it.
    ImageHeader environment;
};

/// The defaults of unset fields: algorithm "pt", the algorithm's native budget unit with 16 per
/// pixel, RenderSettings' defaults for everything else.
grpc::Status validateJobSpec(const pb::JobSpec& spec, const ServiceLimits& limits,
                             ValidatedSpec& out);

/// The checks every upload's files pass, sent inside SubmitJob or streamed (upload_staging.h): a
/// resource uri is UTF-8, relative and inside the scene's folder, and given once (`seen` holds
/// the uris before it); all files together are within --max-upload-mb (RESOURCE_EXHAUSTED).
grpc::Status checkUploadedUri(const std::string& uri, std::set<std::string>& seen);
grpc::Status checkUploadSize(uint64_t bytes, const ServiceLimits& limits);

/// validateJobSpec without the scene checks: for a stored spec (whose scene bytes live in the
/// store) when the job runs.
grpc::Status settingsFromSpec(const pb::JobSpec& spec, const ServiceLimits& limits,
                              ValidatedSpec& out);

/// Reads the header of the environment image `v` names (an uploaded resource, or a file of the
/// named scene's folder found through `scenes`) into v.environment, before it is ever decoded:
/// INVALID_ARGUMENT for more pixels than the core accepts (kMaxEnvironmentPixels). An image
/// that cannot be read now is left to fail the job when it runs, with the loader's message.
grpc::Status checkEnvironmentImage(const pb::JobSpec& spec, const SceneSource& scenes,
                                   const ServiceLimits& limits, ValidatedSpec& v);
/// The same with the image's bytes read by `readResource(uri)` (a staged upload's).
grpc::Status checkEnvironmentImage(
    const std::function<std::vector<uint8_t>(const std::string&)>& readResource, ValidatedSpec& v);

/// The scene as listings, logs and metadata name it: the scene name, an upload's file name
/// (scene_file), or "upload".
std::string sceneLabel(const pb::JobSpec& spec);

/// The spec as stored and echoed back: the scene bytes replaced by nothing (an upload keeps its
/// oneof case and its resource names, so clients can still tell it was an upload).
pb::JobSpec withoutSceneBytes(const pb::JobSpec& spec);

}  // namespace partita::server
