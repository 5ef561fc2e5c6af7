#include "job_memory.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "film.h"
#include "integrators/layer_survey.h"
#include "integrators/mlt/mlt_settings.h"
#include "integrators/partitioned/partitioned_settings.h"
#include "mcmc/bootstrap.h"
#include "mcmc/startup_rule.h"

namespace partita::server {

namespace {

// A film keeps exact 24-byte sums (film.h, Film::kBytesPerSum): its combined ones for every
// pixel (tiles padded to 16x16), and those of its kept types and "other" where they occur
// (type_layers.h: at most `layers` + 1 buffers a pixel, whatever the scene and the budget).
// The kept types are the largest ones, but not every one reaches every pixel: on bathroom
// (pt, 1920x1080, 32 layers) the 33 type buffers held 0.53 of the dense size. Counted at
// kTypeCoverage of it.
constexpr double kSum = Film::kBytesPerSum;
constexpr double kTypeCoverage = 0.6;
constexpr double kImageLayer = 12;  // a resolved layer: dense float RGB, bytes per pixel
constexpr double kPng = 3;  // a layer's PNG of a preview frame at most (8-bit RGB, uncompressed)
constexpr double kPreviewFrames = 2;  // the job's latest and one a slow watcher still holds
constexpr double kRawCopies = 3;      // a raw frame's message, its wire form, one still sent
constexpr double kPartition = 12;     // bytes per pixel and partition image
// The chains' error estimate (mcmc/chain_error_monitor.h) resolves a partition's two halves and
// a sum beside the films for a moment: three images (measured: +71 MiB at 1920x1080).
constexpr double kEstimateImages = 3;
constexpr double kSceneFactor = 4;
constexpr double kBaseline = 8 << 20;  // job record, queues, per-job threads' stacks

bool hasPartitions(const std::string& algorithm) {
    return algorithm == "partitioned" || algorithm == "guided";
}

/// The partitions of a partitioned method's job: K (its parameter "k", or the default), the
/// complement and, when the estimators are chosen with the direct light apart, the direct
/// light's (partition/partition.h).
int partitionsOf(const RenderSettings& s) {
    const PartitionedSettings p = partitionedParameters().resolve(s.parameters);
    const bool directApart = p.direct == "per-pixel" && p.estimators != "chains";
    return std::max(0, p.k) + 1 + (directApart ? 1 : 0);
}

/// Films an algorithm holds at once: pt and bdpt two (bdpt's light tracing splats into its
/// camera film), the second the combined sums of the odd sample indices (the error estimate's
/// half B, sample_passes.h), whose estimate keeps two images more (12 bytes a pixel each,
/// half_split_error.h), partitioned and guided two per partition (partitionsOf), which
/// keep no type layers: its chains' and its odd chains' (the error estimate,
/// mcmc/chain_runner.h's PerGroupWithHalves). mlt two: the chains' (with the type layers) and
/// the odd half's combined image; with the direct light per pixel (its default) four: and the
/// direct light's film (its types are not the chains', so the type buffers are counted once)
/// and its error estimate's two images (12 bytes a pixel each, half_split_error.h).
int filmCount(const std::string& algorithm, const RenderSettings& s) {
    if (hasPartitions(algorithm)) return 2 * partitionsOf(s);
    if (algorithm == "mlt") return mltParameters().resolve(s.parameters).direct != "chains" ? 4 : 2;
    return 2;
}

/// Type buffers a pixel of the film may hold: the kept types and "other" (none for the
/// partitions' films, nor with 0 layers).
int typeBuffers(const std::string& algorithm, const RenderSettings& s) {
    if (hasPartitions(algorithm) || s.maxTypeLayers <= 0) return 0;
    return std::min(s.maxTypeLayers, 1024) + 1;
}

/// guided's guides (core/guide/): what it keeps, the G-buffer (40 B a pixel) and one bit a
/// pixel and partition, and what its denoiser holds for a moment besides (docs/guide-buffers.md,
/// "Guide buffers"): per partition its pre-pass image, its interleaved input and output and
/// its denoised image (4 B each a pixel), and the tap guides (32 B a pixel).
double guideBytes(int partitions, double pixels) {
    double kept = pixels * (40 + double(partitions) / 8);
    double denoising = pixels * (16 * double(partitions) + 32);
    return kept + denoising;
}

/// bdpt's light-tracing splats: a pass is rendered in batches of 256 tiles (65536 pixels) of
/// at most 2^18 pixel samples, each leaving a few splats of 40 bytes (4 tent copies of 32 bytes,
/// twice, while they are summed), and a start index per pixel for their sort.
double bdptExtraBytes(double pixels) {
    const double passSpp = std::max(1.0, std::floor(double(1 << 18) / std::max(1.0, pixels)));
    const double batchSamples = std::min(pixels, 65536.0) * passSpp;
    return batchSamples * 4 * (40 + 2 * 4 * 32) + pixels * 4;
}

/// mlt's own extra memory, with the defaults of MltSettings (integrators/mlt/mlt_settings.h):
/// - the bootstrap's candidates, 40 B each (BootstrapCandidate, mcmc/bootstrap.h), measured
///   12-14 a sample on the shipped scenes (0.7 on door-ajar): the blocks merge into one list
///   wave by wave (sample_waves.h), the list reserved at kCandidatesPerSample a sample, and it
///   lives on through the render. Counted as one list of 14 records a sample (cornell at 2^20
///   samples: 503 MiB of growth against 599 estimated);
/// - each chain's state: two paths of up to max depth + 2 vertices and the mutations' scratch,
///   ~16 KiB (its splats go straight into the film: chain_runner.h).
/// The job's own settings (its bootstrap samples, chains) count, with the defaults for the rest.
struct MltExtra {
    double bootstrap, chains;
};

/// The chains' states (as above).
double chainBytes(int chains) {
    constexpr double kChainStateBytes = 16 << 10;
    return double(chains) * kChainStateBytes;
}

MltExtra mltExtraBytes(const RenderSettings& s) {
    const MltSettings defaults = mltParameters().resolve(s.parameters);
    constexpr double kCandidateBytes = sizeof(BootstrapCandidate);
    uint64_t samples = StartupRule::bootstrapSamples(defaults.bootstrapSamples, s);
    MltExtra e;
    e.bootstrap = double(samples) * kCandidatesPerSample * kCandidateBytes;
    e.chains = chainBytes(defaults.chains);
    return e;
}

/// partitioned's own extra memory, with the defaults of PartitionedSettings
/// (integrators/partitioned/partitioned_settings.h), besides its K + 1 films:
/// - the pre-pass's half-B records, 40 B each (partition/prepass.h), ~13 a sample as measured
///   for mlt's bootstrap, for half the samples, at most the pre-pass's memory budget;
/// - the chains' states as for mlt (the same number of chains over all partitions).
MltExtra partitionedExtraBytes(const RenderSettings& s) {
    const PartitionedSettings defaults = partitionedParameters().resolve(s.parameters);
    constexpr double kRecordsPerSample = 13, kRecordBytes = sizeof(BootstrapCandidate);
    uint64_t samples = StartupRule::bootstrapSamples(defaults.bootstrapSamples, s);
    MltExtra e;
    e.bootstrap = std::min(double(samples) / 2 * kRecordsPerSample * kRecordBytes,
                           double(defaults.prepassMemoryBytes));
    e.chains = chainBytes(defaults.chains);
    return e;
}

/// The layers of the job's frames: the combined one and the type layers with "other"; for the
/// partitioned methods one a partition (K + 1) and the combined one.
int frameLayers(const std::string& algorithm, const RenderSettings& s) {
    int partitions = hasPartitions(algorithm) ? partitionsOf(s) : 0;
    return 1 + (partitions > 0 ? partitions : typeBuffers(algorithm, s));
}

}  // namespace

std::string humanBytes(double b) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    int u = 0;
    while (b >= 1024 && u < 4) {
        b /= 1024;
        ++u;
    }
    char buf[32];
    std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : "%.1f %s", b, units[u]);
    return buf;
}

uint64_t rawPreviewBytes(const std::string& algorithm, const RenderSettings& s) {
    return uint64_t(frameLayers(algorithm, s)) * uint64_t(s.width) * uint64_t(s.height) * 12;
}

MemoryEstimate estimateJobMemory(const std::string& algorithm, const RenderSettings& s,
                                 uint64_t sceneBytes,
                                 int /*renderThreads: no algorithm keeps a film per thread*/,
                                 const ImageHeader& environment, uint64_t rawPreviewLimit) {
    const int tile = 16;
    double padded =
        double((s.width + tile - 1) / tile * tile) * ((s.height + tile - 1) / tile * tile);
    double pixels = double(s.width) * s.height;
    int films = filmCount(algorithm, s);
    int partitions = hasPartitions(algorithm) ? partitionsOf(s) : 0;
    int typeLayers = typeBuffers(algorithm, s);
    int layers = frameLayers(algorithm, s);

    // The film, and what the job holds beside it: preview frames for watchers (when it sends
    // previews) with their PNGs and raw forms (job_memory.h). The final image is made as the
    // film is consumed (Film::takeResolved), so the two are counted as the larger, not their
    // sum.
    double film = padded * kSum * (films + kTypeCoverage * typeLayers);
    double finalImage = layers * pixels * kImageLayer;
    double raw = std::min(double(rawPreviewBytes(algorithm, s)), double(rawPreviewLimit));
    double preview =
        s.previewIntervalSeconds > 0
            ? kPreviewFrames * layers * pixels * (kImageLayer + kPng) + kRawCopies * raw
            : 0;
    const bool samplePasses = algorithm == "pt" || algorithm == "bdpt";
    double errorImages = samplePasses ? 2 * pixels * kImageLayer : 0;
    double images = preview + errorImages + std::max(0.0, finalImage - film);
    // Every partition's image, at most: a per-pixel partition's is made when its phase ends and
    // held through the chains' (beside the films of the others), a chains' partition's when its
    // films go at the end (ChainRunner::takeGroupCombined).
    double parts = partitions * pixels * kPartition;
    double scene = kSceneFactor * double(sceneBytes);
    double splats = algorithm == "bdpt" ? bdptExtraBytes(pixels) : 0;
    // pt's and bdpt's layer survey (integrators/layer_survey.h): a film of every type over at
    // most kSurveyPixels pixels, allowed 128 type buffers a pixel.
    double survey =
        samplePasses && typeLayers > 0 ? std::min(pixels, double(kSurveyPixels)) * kSum * 128 : 0;
    MltExtra mlt{0, 0};
    if (algorithm == "mlt") mlt = mltExtraBytes(s);
    if (hasPartitions(algorithm)) mlt = partitionedExtraBytes(s);
    double mltBytes = mlt.bootstrap + mlt.chains;
    // Partitions estimated per pixel (partition/per_pixel_partitions.h, unless every partition
    // has chains): the per-pixel phase's film (the combined sums and one a per-pixel
    // partition: K + 3 sums a pixel at most; with a time budget one more, the odd samples'
    // combined sums that re-read its share) and bdpt's splats, the per-pixel estimator it may
    // be. Before it, the pilots hold less: the per-pixel pilot one film over at most 65536
    // pixels' samples, the chains' pilot one partition's two halves at a time
    // (partition/effort_pilot.h). The phase ends with its partitions' images made (after its
    // splats are gone) and its film given back before the chains' films are made, so the two
    // phases are counted as the larger, not their sum. In the chains' phase a partition holds
    // either its two films or its image (12 B a pixel against 48): the films of every
    // partition bound both, and the images made at the end as the films go.
    double perPixel = 0;
    if (hasPartitions(algorithm)) {
        const PartitionedSettings p = partitionedParameters().resolve(s.parameters);
        if (p.estimators != "chains")
            perPixel = padded * kSum * (partitions + 1 + (s.budgetKind == BudgetKind::Seconds)) +
                       std::max(bdptExtraBytes(pixels), parts);
        else if (p.allocation != "p")  // the chains' pilot alone: two halves of one partition
            perPixel = padded * kSum * 2;
    }
    const double chainsPhase = film + (partitions > 0 ? kEstimateImages * pixels * kImageLayer : 0);
    const double filmOrPerPixel = std::max(chainsPhase, perPixel);
    double guides = algorithm == "guided" ? guideBytes(partitions, pixels) : 0;
    // An environment image while it loads: the decoded channels (4 B each), its RGB copy and
    // the map's importance tables (environment_map.h: 12 + 8 B a pixel).
    double sky = double(environment.pixels()) * (4.0 * environment.channels + 20);
    MemoryEstimate e;
    e.bytes = uint64_t(filmOrPerPixel + images + splats + survey + mltBytes + guides + scene + sky +
                       kBaseline);
    char buf[256];
    std::snprintf(buf, sizeof buf, "%dx%d: %d film%s %s (%d type buffers), %d layers %s", s.width,
                  s.height, films, films == 1 ? "" : "s", humanBytes(film).c_str(), typeLayers,
                  layers, humanBytes(images).c_str());
    e.breakdown = buf;
    if (partitions > 0)
        e.breakdown += ", " + std::to_string(partitions) + " partitions " + humanBytes(parts);
    if (survey > 0) e.breakdown += ", layer survey " + humanBytes(survey);
    if (splats > 0) e.breakdown += ", bdpt splats " + humanBytes(splats);
    if (mltBytes > 0)
        e.breakdown += (hasPartitions(algorithm) ? ", pre-pass records " : ", mlt bootstrap ") +
                       humanBytes(mlt.bootstrap) + ", chains " + humanBytes(mlt.chains);
    if (perPixel > 0) e.breakdown += ", pilots and per-pixel partitions " + humanBytes(perPixel);
    if (guides > 0) e.breakdown += ", guides " + humanBytes(guides);
    e.breakdown += ", scene " + humanBytes(scene);
    if (sky > 0) e.breakdown += ", environment " + humanBytes(sky);
    return e;
}

uint64_t physicalMemoryBytes() {
    long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
    uint64_t bytes = pages > 0 && size > 0 ? uint64_t(pages) * uint64_t(size) : 0;
    // In a container the cgroup's limit is what the kernel enforces (cgroup v2; "max": none).
    std::ifstream cgroup("/sys/fs/cgroup/memory.max");
    uint64_t limit = 0;
    if (cgroup >> limit && limit > 0 && (bytes == 0 || limit < bytes)) bytes = limit;
    return bytes;
}

}  // namespace partita::server
