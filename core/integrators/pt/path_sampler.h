// One camera path of the unidirectional path tracer: next-event estimation with multiple
// importance sampling (power heuristic) against BSDF sampling, Russian roulette, a maximum
// depth, and Beer-Lambert absorption inside KHR_materials_volume media.
//
// Every complete path the sampler forms (a BSDF-sampled ray hitting an emitter, or a
// next-event connection to a light) is reported to a ContributionSink with its Heckbert type
// and its MIS-weighted contribution C = w f / p. Because the sampler draws only from the Rng it
// is given, re-running it from the same Rng state reproduces the same contributions in the same
// order; `index` numbers them, which is how the pre-pass (paper Section 4.2) regenerates a path.
#pragma once

#include <cstdint>

#include "math/vec.h"
#include "path_type.h"
#include "ray.h"
#include "rng.h"

namespace partita {

class RenderScene;

struct PathContribution {
    PathType type;
    Rgb value{0.0f};  // MIS-weighted contribution of this complete path
    int index = 0;    // ordinal of this contribution within the camera path
    bool viaNextEvent = false;
};

class ContributionSink {
  public:
    virtual ~ContributionSink() = default;
    virtual void add(const PathContribution& contribution) = 0;
};

struct PathSamplerSettings {
    int maxDepth = 16;           // maximum number of scattering vertices
    int rouletteStartDepth = 3;  // Russian roulette from this many scattering vertices on
};

struct PathCounters {
    uint64_t rays = 0;  // closest-hit plus occlusion queries
};

/// Traces the camera path that starts with `primary` (a unit direction, as Camera::generateRay
/// gives) and reports its contributions.
void samplePath(const RenderScene& scene, const Ray& primary, Rng& rng,
                const PathSamplerSettings& settings, ContributionSink& sink,
                PathCounters& counters);

class FilmSink;
/// The same path, its contributions added straight to one film pixel: the path tracer's hot
/// loop, without a virtual call per contribution (the sampler is compiled for both sinks).
void samplePath(const RenderScene& scene, const Ray& primary, Rng& rng,
                const PathSamplerSettings& settings, FilmSink& sink, PathCounters& counters);

struct SurfaceHit;
/// One camera path's start: its primary ray, random numbers and film pixel, and the primary
/// ray's closest hit when it was already traced (in a packet with its neighbours): `traced`,
/// and `hit` null for a miss.
struct PathStart {
    Ray primary;
    Rng& rng;
    FilmSink& sink;
    bool traced = false;
    const SurfaceHit* hit = nullptr;
};
/// samplePath from a PathStart (whose primary ray may have been traced already).
void samplePath(const RenderScene& scene, const PathStart& path,
                const PathSamplerSettings& settings, PathCounters& counters);
/// Two independent paths, traced in lockstep (a vertex of one, then of the other). Each path's
/// contributions, and their order, are exactly those of samplePath; only the interleaving of the
/// two differs, so the paths should go to different pixels for a pixel's sums to be unchanged.
void samplePathPair(const RenderScene& scene, const PathStart& a, const PathStart& b,
                    const PathSamplerSettings& settings, PathCounters& counters);

}  // namespace partita
