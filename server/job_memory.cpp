#include "job_memory.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

namespace partita::server {

namespace {

constexpr double kFilmCombined = 12, kFilmTypeAllowance = 24;  // bytes per pixel
constexpr double kLayerCopies = 3 * 12 + 12 + 1;               // bytes per pixel and layer
constexpr double kPartition = 12;                              // bytes per pixel and partition
constexpr double kSceneFactor = 4;
constexpr double kBaseline = 8 << 20;  // job record, queues, per-job threads' stacks

bool splatsAnywhere(const std::string& algorithm) {
    return algorithm == "mlt" || algorithm == "partitioned" || algorithm == "guided";
}

/// Films an algorithm holds at once: one per render thread for the MCMC family; bdpt keeps a
/// camera film and a light-tracing film and sums them into a third to resolve.
int filmCount(const std::string& algorithm, int renderThreads) {
    if (splatsAnywhere(algorithm)) return std::max(1, renderThreads);
    return algorithm == "bdpt" ? 3 : 1;
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
    double perPixelCap = 24000;
    double spp = s.budgetKind == BudgetKind::Seconds ? 1e9 : s.budget;
    double films = pixels * std::min(1600 * std::sqrt(std::max(1.0, spp)), perPixelCap);
    double splats = std::min(pixels, double(1 << 18)) * 4 * (40 + 4 * 32) + pixels * 4;
    return films + splats;
}

bool hasPartitions(const std::string& algorithm) {
    return algorithm == "partitioned" || algorithm == "guided";
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
                                 uint64_t sceneBytes, int renderThreads) {
    const int tile = 16;
    double padded =
        double((s.width + tile - 1) / tile * tile) * ((s.height + tile - 1) / tile * tile);
    double pixels = double(s.width) * s.height;
    int films = filmCount(algorithm, renderThreads);
    int layers = std::max(0, s.maxTypeLayers) + 2;  // combined and "other" too
    int partitions = hasPartitions(algorithm) ? std::max(1, s.partitions) : 0;

    double film = films * padded * (kFilmCombined + kFilmTypeAllowance);
    double images = layers * pixels * kLayerCopies;
    double parts = partitions * pixels * kPartition;
    double scene = kSceneFactor * double(sceneBytes);
    double splats = algorithm == "bdpt" ? bdptExtraBytes(s, pixels) : 0;
    MemoryEstimate e;
    e.bytes = uint64_t(film + images + parts + splats + scene + kBaseline);
    char buf[256];
    std::snprintf(buf, sizeof buf, "%dx%d: %d film%s %s, %d layers %s", s.width, s.height, films,
                  films == 1 ? "" : "s", humanBytes(film).c_str(), layers,
                  humanBytes(images).c_str());
    e.breakdown = buf;
    if (partitions > 0)
        e.breakdown += ", " + std::to_string(partitions) + " partitions " + humanBytes(parts);
    if (splats > 0) e.breakdown += ", bdpt types and splats " + humanBytes(splats);
    e.breakdown += ", scene " + humanBytes(scene);
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
