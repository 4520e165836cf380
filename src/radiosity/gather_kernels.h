#pragma once
// The inner loop of every gather, G_i += sum_j F_ij B_j over a run of one CSR row's entries,
// for all m wavelengths at once (B row-major, so one F_ij meets m contiguous values), chosen
// once per solve by m and the CPU: fixed-m loops the compiler vectorises, and on x86-64
// hand-written AVX2 / AVX-512 variants (four interleaved partial sums, so consecutive fused
// multiply-adds do not wait on each other). Each variant sums a row's entries in a fixed
// order, so results never depend on the thread count; variants may differ from each other in
// the last bits (FMA, order).
#include <cstddef>
#include <cstdint>

namespace daisy {

// Asks for the cache lines of `count` values at `row` ahead of their use. The gathers read
// rows in an order the hardware prefetcher cannot guess (a sparse row's columns, a node's
// links' sources) and would otherwise wait on memory for each: asking kPrefetchAhead entries
// early made the quarter-million-triangle interior's solve 1.3x faster.
template <typename T>
[[gnu::always_inline]] inline void prefetchRow(const T* row, std::size_t count) {
    const char* bytes = reinterpret_cast<const char*>(row);
    const std::size_t size = count * sizeof(T);
    for (std::size_t offset = 0; offset < size; offset += 64)
        __builtin_prefetch(bytes + offset);
    __builtin_prefetch(bytes + size - 1);  // the last line, when the row straddles one more
}
inline constexpr uint64_t kPrefetchAhead = 8;

// acc[0..m) += sum_{p in [begin, end)} values[p] * radiosity[columns[p] * m + 0..m).
// T is the type B is read as: double, or float for the solver's mixed-precision mirror, where
// runs of 64 products are summed in float before joining the double sums (solver.h).
template <typename T>
using AccumulateFn = void (*)(const uint32_t* columns, const float* values, uint64_t begin,
                              uint64_t end, const T* radiosity, std::size_t m, double* acc);

// The fastest kernel for m samples on this CPU (instantiated for double and float).
template <typename T>
AccumulateFn<T> accumulateFor(std::size_t m);

}  // namespace daisy
