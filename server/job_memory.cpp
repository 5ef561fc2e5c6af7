#include "job_memory.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "film.h"
#include "integrators/mlt/mlt_settings.h"
#include "integrators/partitioned/partitioned_settings.h"
#include "mcmc/bootstrap.h"

namespace partita::server {

namespace {

// A film keeps exact 24-byte sums (film.h, Film::kBytesPerSum). The per-pixel figures below
// that were measured with the earlier 12-byte float sums are doubled (marked "x2").
constexpr double kSum = Film::kBytesPerSum;
constexpr double kFilmCombined = kSum, kFilmTypeAllowance = 2 * kSum;  // bytes per pixel
constexpr double kLayerCopies = 3 * 12 + 12 + 1;                       // bytes per pixel and layer
constexpr double kPartition = 12;  // bytes per pixel and partition
constexpr double kSceneFactor = 4;
constexpr double kBaseline = 8 << 20;  // job record, queues, per-job threads' stacks

bool hasPartitions(const std::string& algorithm) {
    return algorithm == "partitioned" || algorithm == "guided";
}

/// Films an algorithm holds at once: bdpt keeps a camera film and a light-tracing film and sums
/// them into a third to resolve; mlt splats every chain into one film, round by round, in chain
/// order; partitioned and guided have one film per partition group (K and the complement).
/// K of a partitioned method's job (its parameter "k", or the default).
int partitionsOf(const RenderSettings& s) {
    return partitionedParameters().resolve(s.parameters).k;
}

int filmCount(const std::string& algorithm, const RenderSettings& s) {
    if (hasPartitions(algorithm)) return std::max(0, partitionsOf(s)) + 1;
    return algorithm == "bdpt" ? 3 : 1;
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

/// bdpt's own extra memory. Its films hold far more distinct types per pixel than pt's (every
/// (s, t) strategy combines a camera prefix with a light suffix, and light tracing scatters long
/// types everywhere), and their sparse type blocks fill up as samples accumulate: measured on
/// cornell-glass (~1000 types) at 512x384, 1.6 KB a pixel at 1 spp, 3.1 at 4, 6.3 at 16, so
/// about 1.6 KB sqrt(spp), bounded by what ~1000 types of 12 B a pixel in two films can take.
/// Time budgets are counted at that bound. Plus the per-pass light-tracing splats: passes are
/// kept to 2^18 pixel samples, each leaving a few splats of 40 bytes (4 tent copies of 32 bytes
/// while they are summed).
double bdptExtraBytes(const RenderSettings& s, double pixels) {
    double perPixelCap = 2 * 24000;  // x2
    double spp = s.budgetKind == BudgetKind::Seconds ? 1e9 : s.budget;
    double films = pixels * std::min(2 * 1600 * std::sqrt(std::max(1.0, spp)), perPixelCap);
    double splats = std::min(pixels, double(1 << 18)) * 4 * (40 + 4 * 32) + pixels * 4;
    return films + splats;
}

/// mlt's own extra memory, with the defaults of MltSettings (integrators/mlt/mlt_settings.h):
/// - the bootstrap's candidates, 40 B each (BootstrapCandidate, mcmc/bootstrap.h), measured
///   12-14 a sample on the shipped scenes (0.7 on door-ajar): the blocks merge into one list
///   wave by wave (sample_waves.h), the list reserved at kCandidatesPerSample a sample, and it
///   lives on through the render. Counted as one list of 14 records a sample (cornell at 2^20
///   samples: 503 MiB of growth against 599 estimated);
/// - each chain's splats of one round (2 per mutation, 40 B: raster, type, value), and its
///   state: two paths of up to max depth + 2 vertices and the mutations' scratch, ~16 KiB;
/// - the film's type blocks: chains splat every type anywhere, so tiles gather types as the
///   mutations accumulate: measured on cornell-glass (peak RSS over mpp 1), 140 B a pixel at 4
///   mpp and 225 at 16 (512x384), 190 at 64 and 770 at 256 (128x96): counted as 150 B
///   sqrt(mpp), bounded by what ~1000 types of 12 B a pixel can take (time budgets at that
///   bound).
/// The job's own settings (its bootstrap samples, chains) count, with the defaults for the rest.
struct MltExtra {
    double bootstrap, chains, types;
};

/// The chains' splats and states (as above), for `chains` chains of rounds of `roundMutations`.
double chainBytes(int chains, uint64_t roundMutations, double pixels) {
    constexpr double kSplatBytes = 40, kChainStateBytes = 16 << 10;
    double splats = 2 * double(roundMutations) * kSplatBytes;
    // The shared SplatBuffer sums one chain's splats at a time: 4 tent copies of 32 B, twice
    // (buffered and sorted), and a start index per pixel.
    double buffer = 2 * double(roundMutations) * 4 * 32 * 2 + 4 * pixels;
    return double(chains) * (splats + kChainStateBytes) + buffer;
}

/// The type blocks of a film that every type splats into (mlt's film, as above).
double anyTypeBlocks(const RenderSettings& s, double pixels) {
    double mpp = s.budgetKind == BudgetKind::Seconds ? 1e12 : s.budget;
    return pixels * std::min(2 * 150 * std::sqrt(std::max(1.0, mpp)), 2 * 12000.0);  // x2
}

MltExtra mltExtraBytes(const RenderSettings& s, double pixels) {
    const MltSettings defaults = mltParameters().resolve(s.parameters);
    constexpr double kCandidateBytes = sizeof(BootstrapCandidate);
    uint64_t samples = defaults.bootstrapSamples;
    MltExtra e;
    e.bootstrap = double(samples) * kCandidatesPerSample * kCandidateBytes;
    e.chains = chainBytes(defaults.chains, defaults.roundMutations, pixels);
    e.types = anyTypeBlocks(s, pixels);
    // With the direct light per pixel (the default), the chains splat into two films (two
    // halves of about the same types, each with half the mutations: sqrt(2) of one film's
    // blocks) summed into a third to resolve; the direct light's film holds its few types.
    if (defaults.direct != "chains") e.types *= 2.5;
    return e;
}

/// partitioned's own extra memory, with the defaults of PartitionedSettings
/// (integrators/partitioned/partitioned_settings.h), besides its K + 1 films:
/// - the pre-pass's half-B records, 40 B each (partition/prepass.h), ~13 a sample as measured
///   for mlt's bootstrap, for half the samples, at most the pre-pass's memory budget;
/// - the chains' splats and states as for mlt (the same number of chains over all partitions);
/// - the complement's film gathers every other type as mlt's film does; a partition's film
///   holds one type mostly, which the film allowance covers.
MltExtra partitionedExtraBytes(const RenderSettings& s, double pixels) {
    const PartitionedSettings defaults = partitionedParameters().resolve(s.parameters);
    constexpr double kRecordsPerSample = 13, kRecordBytes = sizeof(BootstrapCandidate);
    uint64_t samples = defaults.bootstrapSamples;
    MltExtra e;
    e.bootstrap = std::min(double(samples) / 2 * kRecordsPerSample * kRecordBytes,
                           double(defaults.prepassMemoryBytes));
    e.chains = chainBytes(defaults.chains, defaults.roundMutations, pixels);
    e.types = anyTypeBlocks(s, pixels);
    return e;
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

MemoryEstimate estimateJobMemory(const std::string& algorithm, const RenderSettings& s,
                                 uint64_t sceneBytes,
                                 int /*renderThreads: no algorithm keeps a film per thread*/,
                                 const ImageHeader& environment) {
    const int tile = 16;
    double padded =
        double((s.width + tile - 1) / tile * tile) * ((s.height + tile - 1) / tile * tile);
    double pixels = double(s.width) * s.height;
    int films = filmCount(algorithm, s);
    int partitions = hasPartitions(algorithm) ? std::max(0, partitionsOf(s)) + 1 : 0;
    // The result's images: the combined one and "other" besides the type layers; for the
    // partitioned methods one a partition (K + 1) and the combined one, while each partition's
    // film is resolved with its type layers one partition at a time.
    int typeLayers = std::max(0, s.maxTypeLayers) + 2;
    int layers = partitions > 0 ? partitions + 1 + typeLayers : typeLayers;

    double film = films * padded * (kFilmCombined + kFilmTypeAllowance);
    double images = layers * pixels * kLayerCopies;
    double parts = partitions * pixels * kPartition;
    double scene = kSceneFactor * double(sceneBytes);
    double splats = algorithm == "bdpt" ? bdptExtraBytes(s, pixels) : 0;
    MltExtra mlt{0, 0, 0};
    if (algorithm == "mlt") mlt = mltExtraBytes(s, pixels);
    if (hasPartitions(algorithm)) mlt = partitionedExtraBytes(s, pixels);
    double mltBytes = mlt.bootstrap + mlt.chains + mlt.types;
    double guides = algorithm == "guided" ? guideBytes(partitions, pixels) : 0;
    // An environment image while it loads: the decoded channels (4 B each), its RGB copy and
    // the map's importance tables (environment_map.h: 12 + 8 B a pixel).
    double sky = double(environment.pixels()) * (4.0 * environment.channels + 20);
    MemoryEstimate e;
    e.bytes =
        uint64_t(film + images + parts + splats + mltBytes + guides + scene + sky + kBaseline);
    char buf[256];
    std::snprintf(buf, sizeof buf, "%dx%d: %d film%s %s, %d layers %s", s.width, s.height, films,
                  films == 1 ? "" : "s", humanBytes(film).c_str(), layers,
                  humanBytes(images).c_str());
    e.breakdown = buf;
    if (partitions > 0)
        e.breakdown += ", " + std::to_string(partitions) + " partitions " + humanBytes(parts);
    if (splats > 0) e.breakdown += ", bdpt types and splats " + humanBytes(splats);
    if (mltBytes > 0)
        e.breakdown += (hasPartitions(algorithm) ? ", pre-pass records " : ", mlt bootstrap ") +
                       humanBytes(mlt.bootstrap) + ", chains and splats " + humanBytes(mlt.chains) +
                       (hasPartitions(algorithm) ? ", complement types " : ", types ") +
                       humanBytes(mlt.types);
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
