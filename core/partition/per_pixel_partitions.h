// The partitions estimated per pixel (issue #23 1): instead of chains, a partition may be
// integrated by per-pixel samples restricted to its types: BDPT's (integrators/bdpt/
// bdpt_passes.h) or, in a scene without delta lights (which a path tracer cannot reach through
// specular chains), the path tracer's (cheaper per sample: on cornell-glass 7x). One sample
// of a pixel estimates every per-pixel partition at once: each contribution goes
// to the partition that holds its type, or is dropped when that partition has chains. MIS stays
// exact under the restriction (a path's strategies all give it the same type), so partition g's
// image converges to the full image's layers of g's types, and the chain partitions and the
// per-pixel ones add up to the whole image exactly once.
//
// The film keeps one layer per per-pixel partition, under a key that names the partition (a
// film layer's key, L D^g E, not the type of the paths in it). Every (pixel, sample) has its own
// random stream and the film sums exactly: the images depend on neither the threads, nor the
// passes, nor the shards.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "algorithm.h"
#include "film.h"
#include "integrators/sample_passes.h"
#include "partition/partition.h"

namespace partita {

class SamplePassRenderer;
class ThreadPool;

enum class PerPixelEstimator : uint8_t { Bdpt = 0, PathTracer = 1 };
const char* perPixelEstimatorName(PerPixelEstimator e);

class PerPixelPartitions {
  public:
    /// Estimates the partitions with `perPixel` set (the others' contributions are dropped).
    /// `byParity` (the pilot's): the even and the odd sample indices of each partition under
    /// keys of their own (parityImage), two independent estimates of its image.
    PerPixelPartitions(const RenderContext& ctx, const std::vector<Partition>& partitions,
                       PerPixelEstimator estimator, bool byParity = false);
    ~PerPixelPartitions();
    PerPixelPartitions(PerPixelPartitions&&) = delete;  // ctx_ refers to settings_

    /// Samples [range.first, range.end) of every pixel, on ctx's pool; advances `progress` by
    /// pixels x samples; cancellable.
    void renderPass(SampleRange range, ProgressReporter& progress);
    /// Partition g's image after `spp` samples per pixel: empty when g has chains, black when no
    /// sample reached it. Resolved from the film in place (its memory and the images'); on
    /// `pool` when given.
    std::vector<Image> images(uint64_t spp, ThreadPool* pool = nullptr) const;
    /// images(), bit for bit, consuming the film (each sum buffer given back as its image is
    /// made): the end of the per-pixel phase, whose film the chains' phase no longer needs.
    /// Only rays() afterwards.
    std::vector<Image> takeImages(uint64_t spp, ThreadPool* pool = nullptr);
    Film takeFilm();
    uint64_t rays() const;
    /// Only these film tiles from now on (SamplePassRenderer::renderOnlyTiles).
    void renderOnlyTiles(std::vector<size_t> tiles);
    /// Sums the odd sample indices apart from now on (before the first pass): the samples' own
    /// variance (perSampleLuminanceVariance). A combined-only film: 24 B a pixel.
    void keepOddHalf();
    /// With keepOddHalf, after `spp` samples [0, spp) of every pixel: the per-sample luminance
    /// variance of the per-pixel partitions together, summed over pixels (the even and the
    /// odd indices as two halves, HalfSplitError::perSampleLuminanceVariance); 0 before both
    /// halves have a sample.
    double perSampleLuminanceVariance(uint64_t spp) const;

    /// The film key of partition g (not a path type: a layer's name in this film); byParity,
    /// g's odd samples are under keyOf(partitions + g).
    static PathType keyOf(size_t g);

  private:
    std::vector<Partition> partitions_;
    bool byParity_ = false;
    std::vector<PathType> keys_;  // keyOf(i), i < 2 x partitions (per contribution: looked up)
    /// The job's settings but for the layers kept: every partition's key, whatever --layers.
    RenderSettings settings_;
    RenderContext ctx_;
    std::unique_ptr<SamplePassRenderer> passes_;
};

/// Partition g's image of the even (odd = false) or the odd sample indices in a byParity film
/// of `partitions` partitions (PerPixelPartitions::takeFilm), after `perParity` samples of each
/// per pixel.
Image parityImage(const Film& film, size_t partitions, size_t g, bool odd, uint64_t perParity);

/// The images of the per-pixel partitions from their film (a PerPixelPartitions' or the merged
/// shards') after `spp` samples of every pixel: empty for a partition with chains.
std::vector<Image> perPixelImages(const Film& film, const std::vector<Partition>& partitions,
                                  uint64_t spp);

/// The per-pixel variance of each partition's image from two independent estimates of k samples
/// each: samples [first, first + 2k) of every pixel, `first` a multiple of 2k, the even and the
/// odd indices apart (the two parities' sequences, pixel_sample_position.h: independent, and
/// each block of k points stratified over the pixel). V_g = k x sum over pixels of
/// (L0 - L1)^2 / 2, L the luminance of partition g's k-sample estimate: the error of n samples
/// is V_g / n where the error falls as 1 / n. Stratified samples do better than that for the
/// light seen directly and through glass (pixel edges), which k = 1 cannot see: the path
/// tracer's pilot takes k = 4 (docs/partition-estimators.md, "The per-pixel estimator"). Also
/// the rays of one sample of every pixel. Partitions that are not per pixel get V_g = 0.
///
/// On a large image the pilot looks at part of it: the tiles perPixelPilotTiles keeps (about
/// kPerPixelPilotPixels pixels, scattered over the image), its sums scaled by the image's pixels
/// over theirs. Its time and its films' memory then do not grow with the image (at 1280x720
/// two one-sample films of 13 partitions held ~290 MB each).
struct PerPixelPilot {
    std::vector<double> variance;
    /// The same over pixel-channels (RGB): partition g's image after n samples per pixel has
    /// this / n (the error estimate, issue #26).
    std::vector<double> varianceRgb;
    double raysPerSample = 0;
    double secondsPerSample = 0;
};
/// `perParity`: k.
PerPixelPilot runPerPixelPilot(const RenderContext& ctx, const std::vector<Partition>& partitions,
                               PerPixelEstimator estimator, uint64_t first,
                               ProgressReporter& progress, uint64_t perParity = 1);

inline constexpr double kPerPixelPilotPixels = 65536;
/// The film tiles the pilot renders on a width x height image (row-major indices, ascending):
/// empty (every tile) when the image has at most about kPerPixelPilotPixels pixels, else one
/// tile in `stride`, chosen by a hash of the tile's index (scattered, not in stripes), at least
/// one; and the pixels they hold.
struct PilotTiles {
    std::vector<size_t> tiles;
    double pixels = 0;
};
PilotTiles perPixelPilotTiles(int width, int height);

}  // namespace partita
