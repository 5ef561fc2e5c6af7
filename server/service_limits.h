// What one daemon accepts: the resource limits set on its command line. Requests beyond them are
// RESOURCE_EXHAUSTED; malformed values (negative sizes, out-of-range parameters) are
// INVALID_ARGUMENT (see validation.h).
#pragma once

#include <cstdint>

#include "render_settings.h"

namespace partita::server {

struct ServiceLimits {
    int maxWidth = 8192, maxHeight = 8192;
    double maxSamplesPerPixel = 65536;  // also the limit on mutations per pixel
    double maxSeconds = 24 * 3600.0;
    int64_t maxUploadBytes = int64_t(256) << 20;  // one scene, all its files
    /// Largest request message: an upload inside SubmitJob must fit it (larger scenes stream
    /// through UploadScene). gRPC holds a message being received whole, ~3x its size.
    int64_t maxMessageBytes = int64_t(4) << 20;
    /// What gRPC may hold for requests being received, all connections together (a gRPC
    /// resource quota on the transport's read buffers). gRPC assembles a message whole before
    /// it compares it with maxMessageBytes; beyond this quota it resets streams instead
    /// (RESOURCE_EXHAUSTED), so requests over the limit cannot grow the daemon without bound.
    int64_t maxReceiveBytes = int64_t(256) << 20;
    int maxUploadStreams = 4;        // UploadScene streams in flight at once
    double uploadTtlSeconds = 3600;  // a staged upload no job names is removed after this
    double uploadIdleSeconds = 60;   // an upload silent this long may lose its place
    int maxQueuedJobs = 1000;
    int maxWatchersPerJob = 64;
    int maxWatchStreams = 1024;  // open WatchJob streams of all jobs together
    int maxDepth = 1024;
    uint64_t maxBootstrapSamples = uint64_t(1) << 30;  // the MCMC start-up's samples ("bootstrap")
    int64_t maxJobMemoryBytes = 0;  // largest memory estimate of one job (job_memory.h); 0: none
    int64_t maxTotalJobMemoryBytes = 0;  // what running jobs may use together; 0: no limit
    int64_t maxStoreBytes = 0;           // store size beyond which uploads are refused; 0: none
    /// Largest raw preview frame (every layer as float32 RGB) a watcher may ask for: the
    /// estimate counts a job's raw frames up to this (job_memory.h).
    int64_t maxRawPreviewBytes = int64_t(256) << 20;

    /// The same limits in the core's terms, for partita::validateSettings.
    RenderLimits renderLimits() const;
};

}  // namespace partita::server
