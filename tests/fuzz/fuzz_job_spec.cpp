// libFuzzer target for JobSpec validation (server/validation.h) from random protobuf bytes: a
// SubmitJob request's spec as gRPC would parse it, checked against the default limits, its
// environment image's header read (an uploaded resource, or a file of a shipped scene's folder),
// then stripped of its scene bytes as the store keeps it. Validation answers with a status; it may
// not throw or crash, whatever the spec holds.

#include <cstddef>
#include <cstdint>

#include "proto.h"
#include "quiet_logs.h"
#include "scene_source.h"
#include "validation.h"

namespace ps = partita::server;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    partita::fuzz::quietLogs();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    ps::pb::JobSpec spec;
    if (!spec.ParseFromArray(data, int(size))) return 0;
    static const ps::ServiceLimits limits;
    ps::ValidatedSpec v;
    static const ps::SceneSource scenes(PARTITA_SCENES_DIR);
    if (ps::validateJobSpec(spec, limits, v).ok())
        (void)ps::checkEnvironmentImage(spec, scenes, limits, v);
    (void)ps::sceneLabel(spec);
    (void)ps::withoutSceneBytes(spec).ByteSizeLong();
    return 0;
}
