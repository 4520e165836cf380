#pragma once
// Resident memory of this process, for the per-stage and per-run peaks the render summary and
// `daisy bench` report. Linux: VmHWM / VmRSS of /proc/self/status; the peak can be reset by
// writing "5" to /proc/self/clear_refs (Linux 4.0+, proc(5)). Elsewhere both report 0.
#include <cstdint>

namespace daisy {

// Peak resident set size since start or the last resetPeakResidentBytes(), bytes; 0 if unknown.
uint64_t peakResidentBytes();

// Starts a new peak at the current resident size. False when the system cannot (then
// peakResidentBytes() keeps the process-lifetime peak).
bool resetPeakResidentBytes();

}  // namespace daisy
