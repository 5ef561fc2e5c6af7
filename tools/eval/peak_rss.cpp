#include "eval/peak_rss.h"

#include <malloc.h>
#include <sys/resource.h>

#include <fstream>
#include <string>

namespace partita::eval {

namespace {

/// A "Name:   123 kB" line of /proc/self/status in MiB, or -1.
double statusFieldMb(const std::string& name) {
    std::ifstream f("/proc/self/status");
    std::string line;
    while (std::getline(f, line)) {
        if (line.rfind(name + ":", 0) != 0) continue;
        return std::stod(line.substr(name.size() + 1)) / 1024.0;
    }
    return -1;
}

}  // namespace

double currentRssMb() { return statusFieldMb("VmRSS"); }

double peakRssMb() {
    double hwm = statusFieldMb("VmHWM");
    if (hwm >= 0) return hwm;
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;  // kB on Linux
}

bool resetPeakRss() {
    // Memory an earlier render freed but the allocator kept would otherwise serve the next one
    // without showing as an increase.
    malloc_trim(0);
    std::ofstream f("/proc/self/clear_refs");
    f << "5";
    f.flush();
    return bool(f);
}

}  // namespace partita::eval
