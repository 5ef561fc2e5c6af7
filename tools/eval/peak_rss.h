// Peak resident memory of this process, resettable, so that one process can measure the peak of
// each of several renders in turn (Linux: VmHWM in /proc/self/status, reset by writing "5" to
// /proc/self/clear_refs). Where the reset is refused, the peak stays the process's lifetime
// peak (getrusage's ru_maxrss) and resetPeakRss says so.
#pragma once

namespace partita::eval {

/// Current resident memory in MiB (VmRSS), or -1 when unknown.
double currentRssMb();
/// Peak resident memory in MiB since the last successful reset (VmHWM), else since start.
double peakRssMb();
/// Returns freed heap memory to the system (glibc malloc_trim) and sets the peak to the current
/// resident memory; false when the system refuses the reset.
bool resetPeakRss();

}  // namespace partita::eval
