#include "job_memory.h"

#include <unistd.h>

#include <algorithm>
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
    int films = splatsAnywhere(algorithm) ? std::max(1, renderThreads) : 1;
    int layers = std::max(0, s.maxTypeLayers) + 2;  // combined and "other" too
    int partitions = hasPartitions(algorithm) ? std::max(1, s.partitions) : 0;

    double film = films * padded * (kFilmCombined + kFilmTypeAllowance);
    double images = layers * pixels * kLayerCopies;
    double parts = partitions * pixels * kPartition;
    double scene = kSceneFactor * double(sceneBytes);
    MemoryEstimate e;
    e.bytes = uint64_t(film + images + parts + scene + kBaseline);
    char buf[256];
    std::snprintf(buf, sizeof buf, "%dx%d: %d film%s %s, %d layers %s", s.width, s.height, films,
                  films == 1 ? "" : "s", humanBytes(film).c_str(), layers,
                  humanBytes(images).c_str());
    e.breakdown = buf;
    if (partitions > 0)
        e.breakdown += ", " + std::to_string(partitions) + " partitions " + humanBytes(parts);
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
