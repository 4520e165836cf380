#pragma once
// Resident memory of this process, for the per-stage and per-run peaks the render summary and
// `daisy bench` report. Linux: VmHWM / VmRSS of /proc/self/status; the peak can be reset by
// writing "5" to /proc/self/clear_refs (Linux 4.0+, proc(5)). Elsewhere both report 0.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
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

// std::allocator whose construct() without arguments default-initialises: resize() of a vector
// of trivial elements leaves the new ones unset instead of zeroing them. For arrays of hundreds
// of MB whose every element is written before it is read (F's CSR arrays): zeroing them first
// costs a serial pass over fresh pages, which on a virtual machine is mostly page faults.
template <typename T>
struct DefaultInitAllocator : std::allocator<T> {
    template <typename U>
    struct rebind {
        using other = DefaultInitAllocator<U>;
    };
    DefaultInitAllocator() = default;
    template <typename U>
    DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}

    template <typename U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;
    }
    template <typename U, typename... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

// A vector whose resize() does not initialise trivial elements (see DefaultInitAllocator).
template <typename T>
using UninitializedVector = std::vector<T, DefaultInitAllocator<T>>;

// v.resize(count) on storage advised with adviseHugePages first (when v must grow).
template <typename T, typename Allocator>
void resizeOnHugePages(std::vector<T, Allocator>& v, std::size_t count) {
    if (count > v.capacity()) {
        v.reserve(count);
        adviseHugePages(v.data(), v.capacity() * sizeof(T));
    }
    v.resize(count);
}

}  // namespace daisy
