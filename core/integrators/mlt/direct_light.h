// mlt's direct light apart (issue #22 1; Veach & Guibas 1997 and Mitsuba's `mlt` do the same):
// the paths of the direct-light class, L S* E and L D S* E in Heckbert's light-to-eye notation
// (the light seen directly or through specular surfaces, and one non-specular bounce to the
// light, then specular ones to the eye), are estimated per pixel, and the chains are restricted
// to every other path. A type is in exactly one part, so the two images add up exactly, layer by
// layer.
//
// The per-pixel estimator is a path tracer's: per pixel sample a camera subpath (tent-filtered
// raster position stratified over the pixel's samples by a scrambled (0, 2)-sequence, the rest
// from the sample's own random stream), emitter hits (s = 0) and next-event estimation
// (s = 1) with MIS over those two strategies (path/connection.h's restrictToPathTracer), only
// contributions of direct-class types kept. A light no camera ray can hit (a point or spot
// light) seen directly (L E) is light-traced (s = 1, t = 1: one light vertex per pixel sample,
// splatted as bdpt splats), its only strategy. The camera walk stops at the vertex after its first
// non-specular scattering vertex (WalkSettings::stopAfterNonSpecular): nothing later can be
// direct, and everything before is the full walk's, so the estimate is that of a path tracer
// whose non-direct contributions are dropped. Every (pixel, sample) has its own random stream
// and the film sums exactly: the direct film does not depend on threads, passes or shards.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "algorithm.h"
#include "film.h"
#include "half_split_error.h"
#include "integrators/sample_passes.h"
#include "mcmc/markov_chain.h"
#include "path/random_walk.h"
#include "path_type.h"
#include "splat_buffer.h"
#include "type_layers.h"

namespace partita {

class ProgressReporter;

/// The chains' restriction when direct light is estimated per pixel: every type that is not in
/// the direct-light class.
PathRestriction indirectLightOnly();

/// The per-pixel direct-light estimator, into its own film (resolved with 1 / spp).
class DirectLightRenderer {
  public:
    /// The film keeps `layers` (type_layers.h: an mlt render's, the same as its chains');
    /// `stream`: another value gives independent samples (the pilot's).
    explicit DirectLightRenderer(const RenderContext& ctx, TypeLayers layers = TypeLayers::every(),
                                 uint64_t stream = 0);
    ~DirectLightRenderer();
    /// Samples [range.first, range.end) of every pixel, on ctx's pool (tile by tile, in parts
    /// of at most maxPassSamples()); advances `progress` (when set) by pixels x samples;
    /// cancellable.
    void renderPass(SampleRange range, ProgressReporter* progress);
    const Film& film() const { return film_; }
    Film takeFilm() { return std::move(film_); }
    /// The error estimate of its image (issue #26), kept from the next renderPass on once asked
    /// (a resolve of the combined image after every pass, two images of 12 B a pixel): its
    /// renderPass calls alternate between two halves (one call's samples half A, the next's
    /// half B, ...). Samples stratified across the sample index make it an overestimate: each
    /// half is less stratified than the whole.
    void keepHalves() { keepHalves_ = true; }
    const HalfSplitError& halves() const { return halves_; }
    uint64_t rays() const { return rays_.load(); }
    /// Adds another renderer's film and rays (samples of other indices: the film sums exactly,
    /// so this is the film that rendering them here would give).
    void absorb(const DirectLightRenderer& other);

  private:
    /// A light-tracing splat of L E (a point or spot light seen directly).
    struct Splat {
        Vec2f raster;
        Rgb value;
    };
    /// One tile's splats of a pass, sample by sample (as bdpt's).
    struct TileSplats {
        std::vector<Splat> splats;
        std::vector<uint32_t> sampleStarts;
    };
    uint64_t maxPassSamples() const;
    void renderPassPart(SampleRange range, ProgressReporter* progress);
    void renderTile(int x0, int y0, int x1, int y1, SampleRange range, TileSplats& splats,
                    uint64_t& rays);

    const RenderContext& ctx_;
    Film film_;
    SplatBuffer splatBuffer_;
    std::vector<TileSplats> tiles_;
    WalkSettings walk_, lightWalk_;
    bool lightTracing_ = false;  // the scene has a light that camera rays cannot hit but see
    uint64_t streams_;
    std::atomic<uint64_t> rays_{0};
    HalfSplitError halves_;
    bool keepHalves_ = false;
    bool nextHalfA_ = true;
};

/// The direct part's image after `spp` samples per pixel (as pt's and bdpt's: the film / spp).
LayeredImage resolveDirectLight(const Film& film, uint64_t spp, int maxTypeLayers,
                                ThreadPool* pool);

/// The direct light's pilot: two samples of every pixel, independent of the image's own (a
/// stream of their own), rendered one after the other into a film each, whose combined images
/// give the per-sample variance of the direct image, V_d = sum over pixels of (L0 - L1)^2 / 2
/// (L the luminance of a pixel's one-sample estimate: unbiased for independent samples; the
/// image's stratified samples do better). Each film goes once its image is taken: the pilot
/// holds one film and two images at most (100 MB at 1080p, the peak of a 1080p mlt render
/// with --layers 0 while it held both films). The pilot's samples are not part of the image,
/// so that the samples per pixel the rule draws from them do not depend on the samples they
/// are averaged with.
struct DirectPilot {
    Image image;          // the two samples' mean, combined only (the previews' direct light)
    double variance = 0;  // V_d
    /// The error sums of the pilot's image (its two samples' mean; half_split_error.h): the
    /// previews' direct light until the direct light proper has run (issue #26).
    ErrorSums errorSums;
    double rays = 0;
    double seconds = 0;
};
DirectPilot runDirectPilot(const RenderContext& ctx, ProgressReporter* progress);

/// V_d from the pilot's two samples per pixel and the direct light's own samples so far (its
/// halves, keepHalves), pooled by their counts (half_split_error.h's pooledVariance:
/// (2 V_pilot + n V_own) / (2 + n)). The pilot alone misses what is bright and rare:
/// on pool the light's glints in the water reach a pixel in 1 of ~60 samples, about one hit
/// in four passes over the image, so two pilot samples see none in most seeds and put V_d 10^4
/// times too low (the direct light got 5 samples per pixel, and its glints 90% of the image's
/// squared error). The split rule is re-read with this after each pass of the direct light.
double pooledDirectVariance(double pilotVariance, const HalfSplitError& own);

/// The error of the chains' image, sum over pixels of its variance, from two halves of the
/// chains (independent chains, each half's image resolved with b W H / its own mutations):
/// (I_a - I_b)^2 / 4 summed over pixels, in luminance. The halves come as `all` (both halves'
/// splats) and `half` (half b's alone), so I_a is made of all less half. 0 when a half has no
/// mutation.
double chainHalvesError(const Film& all, const Film& half, uint64_t mutationsA, uint64_t mutationsB,
                        double bValue, int width, int height);

/// The split of the budget between the per-pixel direct light and the chains (issue #22 1),
/// Neyman allocation: with A_d = V_d c_d (the direct image's error times its cost, per sample
/// per pixel: E_d(n) = V_d / n for n samples per pixel costing n c_d) and A_c = E_c T_c (the
/// chains' error times what they cost), the total error A_d / T_d + A_c / T_c with
/// T_d + T_c = T fixed is smallest at T_d / T_c = sqrt(A_d / A_c). Costs are rays for a mutation
/// budget (deterministic: the image depends on neither threads nor timing) and seconds for a
/// time budget. For a mutation budget the chains keep their mutations (T_c is what they cost)
/// and the direct light gets T_d = T_c sqrt(A_d / A_c), so
///   n = T_d / c_d = sqrt(V_d T_c / (E_c c_d)),
/// the samples per pixel returned, within [lo, hi]; `lo` when nothing is measured (no chain).
/// c_d is the cost of one sample of every pixel.
uint64_t neymanDirectSpp(double directVariance, double directCost, double chainError,
                         double chainCost, uint64_t lo, uint64_t hi);
/// The same rule as the share of a total T_d + T_c that goes to the direct light:
/// sqrt(A_d) / (sqrt(A_d) + sqrt(A_c)); 1 when the chains have no error.
double neymanDirectShare(double directVariance, double directCost, double chainError,
                         double chainCost);

/// The sum of two images resolved from films with no path type in common (each resolved with
/// the same `maxTypeLayers`): the combined images added, and the type layers of both ranked
/// together as Film::resolve ranks them (largest total luminance first, ties in PathType
/// order), the first `maxTypeLayers` kept and the rest added into "other" with both parts'
/// "other" layers. A type in the top of the sum is in the top of its own part, so this is the
/// layering the sum of the two films would give. Deterministic (fixed summation orders). The
/// parts are taken by value: pass them with std::move where they are no longer needed.
LayeredImage addDisjointParts(LayeredImage a, LayeredImage b, int maxTypeLayers);

}  // namespace partita
