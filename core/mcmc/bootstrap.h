// The start-up of path-space MLT (Veach 1997, sec. 11.3): N bidirectional samples estimate the
// normalising constant b = integral of f* over path space, and the chains' initial paths are
// resampled from them in proportion to their contributions (sampling-importance-resampling).
//
// Each bootstrap sample is one BDPT sample (connection.h, every strategy, MIS weights) whose
// camera ray goes through a raster position uniform over the camera's importance support
// (path_edits.h): the support of f, so that b is the integral over all of it. A candidate is one
// strategy's path with its weight w f*(x) / p(x); b is the sum of the weights over N. A candidate
// is stored as (sample index, s, t, the pixel it lands in) and its path regenerated on demand: a
// sample's random stream depends only on its index.
//
// Start-up bias: a chain started from a resampled candidate is distributed as f* / b only as N
// grows (the bias is O(1 / N)); Veach's estimate is then unbiased up to that term. No burn-in is
// needed or done (DESIGN.md: the paper's 1024 iterations apply to the partitioned chains).
#pragma once

#include <cstdint>
#include <vector>

#include "mcmc/markov_path.h"
#include "path/random_walk.h"
#include "rng.h"

namespace partita {

class Camera;
class RenderScene;

/// Candidates a bootstrap sample leaves on average, about: 12-14 on the shipped scenes (0.7 on
/// door-ajar). Lists of them reserve this much room, and the daemon's memory estimate counts it.
inline constexpr double kCandidatesPerSample = 14;

/// One start-up path as a record of 40 bytes (static_assert in bootstrap.cpp).
struct BootstrapCandidate {
    uint64_t sample = 0;
    uint16_t s = 0, t = 0;
    float weight = 0;  // w f*(x) / p(x)
    PathType type;
    /// The pixel the path lands in, y * width + x (row 0 at the top): the camera ray's raster
    /// position for t >= 2, the light-tracing splat's (StrategySample::raster) for t == 1,
    /// clamped to the image (the support reaches half a pixel beyond it). For per-partition
    /// pre-pass images (partition/partition_images.h).
    uint32_t pixel = 0;
};

/// The strategies a start-up sample uses: all of BDPT's, or those of a path tracer with
/// next-event estimation and MIS (s <= 1), the paper's pre-pass estimator (Sec. 4.2).
enum class StartupEstimator { Bidirectional, PathTracer };

class BootstrapSampler {
  public:
    BootstrapSampler(const RenderScene& scene, const Camera& camera, int maxDepth, uint64_t seed,
                     StartupEstimator estimator = StartupEstimator::Bidirectional);

    /// The candidates of bootstrap sample `index`, in strategy order; returns their weight sum.
    double sample(uint64_t index, std::vector<BootstrapCandidate>& out, uint64_t& rays) const;
    /// The path of a candidate, regenerated and evaluated (markov_path.h); false when it carries
    /// nothing as a chain state (f* = 0 after all).
    bool regenerate(const BootstrapCandidate& candidate, MarkovPath& out, uint64_t& rays) const;

  private:
    /// Runs sample `index`'s strategies in order; visit(s, t, sample, connector, raster) for
    /// each valid one (raster: the camera ray's), stopping when visit returns false.
    template <typename Visit>
    void forEachStrategy(uint64_t index, uint64_t& rays, bool keepPaths, Visit&& visit) const;

    const RenderScene& scene_;
    const Camera& camera_;
    int maxDepth_;
    uint64_t seed_;
    StartupEstimator estimator_;
    WalkSettings cameraWalk_, lightWalk_;
};

/// Systematic resampling: `count` candidate indices drawn in proportion to their weights (in
/// increasing order), with one uniform from `rng`. Empty when the weights sum to zero.
std::vector<size_t> resampleCandidates(const std::vector<BootstrapCandidate>& candidates,
                                       size_t count, Rng& rng);

/// The same among candidates[members[j]] only (a partition's, without a copy of its records):
/// the positions j in `members` drawn.
std::vector<size_t> resampleCandidates(const std::vector<BootstrapCandidate>& candidates,
                                       const std::vector<uint32_t>& members, size_t count,
                                       Rng& rng);

}  // namespace partita
