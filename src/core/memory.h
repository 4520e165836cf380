#pragma once
// Resident memory of this process, for the per-stage and per-run peaks the render summary and
// `daisy bench` report. Linux: VmHWM / VmRSS of /proc/self/status; the peak can be reset by
// writing "5" to /proc/self/clear_refs (Linux 4.0+, proc(5)). Elsewhere both report 0.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace daisy {

// Peak resident set size since start or the last resetPeakResidentBytes(), bytes; 0 if unknown.
uint64_t peakResidentBytes();

// Starts a new peak at the current resident size. False when the system cannot (then
// peakResidentBytes() keeps the process-lifetime peak).
bool resetPeakResidentBytes();

// Asks the system to back [data, data + bytes) with huge pages where it can (Linux:
// madvise MADV_HUGEPAGE on the whole 4 KiB pages inside the range; a hint, ignored elsewhere or
// when refused). A large array first touched after this faults in 2 MiB at a time instead of
// 4 KiB: on a virtual machine each fault is an exit, so hundreds of MB of fresh memory cost
// seconds of page faults without it.
void adviseHugePages(void* data, std::size_t bytes);

// v.resize(count) on storage advised with adviseHugePages first (when v must grow).
template <typename T>
void resizeOnHugePages(std::vector<T>& v, std::size_t count) {
    if (count > v.capacity()) {
        v.reserve(count);
        adviseHugePages(v.data(), v.capacity() * sizeof(T));
    }
    v.resize(count);
}

}  // namespace daisy
