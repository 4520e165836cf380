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
