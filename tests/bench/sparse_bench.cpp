// Micro-benchmarks of the solver's sparse products (Google Benchmark; not in ctest), in stored
// non-zeros per second: G = F B (gatherAll, double, every wavelength at once), one row kernel
// (accumulateFor, double and the mixed-precision float mirror), the row sums and the transpose
// southwell uses. F is the closed cube room of 6 x 2 x 14^2 = 2,352 patches (every pair of
// different faces visible: 4.6 M non-zeros), built once on the cpu backend with the default
// settings (hybrid, L = 1, 16 rays, seed 1). Run:
//   cmake --build build --target daisy_microbench &&
//   build/daisy_microbench --benchmark_filter='Gather|Accumulate|RowSums|Transpose'
// Results and the commands are recorded in docs/performance.md.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>
#include <vector>

#include "backend/backend.h"
#include "geometry/patch_mesh.h"
#include "radiosity/gather_kernels.h"
#include "radiosity/solver.h"
#include "radiosity/sparse_matrix.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

const SparseMatrix& cubeMatrix() {
    static const std::unique_ptr<SparseMatrix> matrix = [] {
        auto patches = buildPatchMesh(verify::unitCubeRoom(14), 0);
        FormFactorSettings settings;
        settings.progress = false;
        auto f = patches ? makeCpuBackend()->buildFormFactors(*patches, settings)
                         : Expected<FormFactorResult>(patches.error());
        if (!f) std::abort();
        return std::make_unique<SparseMatrix>(std::move(f->matrix));
    }();
    return *matrix;
}

void setNonzeroRate(benchmark::State& state, const SparseMatrix& f) {
    state.counters["nonzeros/s"] = benchmark::Counter(
        double(state.iterations()) * double(f.nonzeroCount()), benchmark::Counter::kIsRate);
}

// G = F B for m wavelengths on `threads` threads: one pass over F per call.
void BM_GatherAll(benchmark::State& state) {
    const SparseMatrix& f = cubeMatrix();
    const auto m = static_cast<std::size_t>(state.range(0));
    const int threads = static_cast<int>(state.range(1));
    std::vector<double> b(std::size_t(f.size) * m, 1.0), g(b.size());
    for (auto _ : state) {
        gatherAll(f, b, m, g, threads);
        benchmark::DoNotOptimize(g.data());
    }
    setNonzeroRate(state, f);
    state.counters["entry-wavelengths/s"] =
        benchmark::Counter(double(state.iterations()) * double(f.nonzeroCount()) * double(m),
                           benchmark::Counter::kIsRate);
}
BENCHMARK(BM_GatherAll)
    ->ArgNames({"m", "threads"})
    ->Args({1, 1})
    ->Args({4, 1})
    ->Args({16, 1})
    ->Args({16, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The row kernel alone, one thread, over every row: B read as double or as float (the solver's
// mixed-precision mirror).
template <typename T>
void accumulateBench(benchmark::State& state) {
    const SparseMatrix& f = cubeMatrix();
    const auto m = static_cast<std::size_t>(state.range(0));
    const AccumulateFn<T> kernel = accumulateFor<T>(m);
    std::vector<T> b(std::size_t(f.size) * m, T(1));
    std::vector<double> acc(m);
    for (auto _ : state) {
        for (uint32_t i = 0; i < f.size; ++i) {
            std::fill(acc.begin(), acc.end(), 0.0);
            kernel(f.columns.data(), f.values.data(), f.rowOffsets[i], f.rowOffsets[i + 1],
                   b.data(), m, acc.data());
            benchmark::DoNotOptimize(acc.data());
        }
    }
    setNonzeroRate(state, f);
}
void BM_AccumulateDouble(benchmark::State& state) {
    accumulateBench<double>(state);
}
void BM_AccumulateFloat(benchmark::State& state) {
    accumulateBench<float>(state);
}
BENCHMARK(BM_AccumulateDouble)
    ->ArgName("m")
    ->Arg(1)
    ->Arg(16)
    ->Arg(35)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AccumulateFloat)
    ->ArgName("m")
    ->Arg(1)
    ->Arg(16)
    ->Arg(35)
    ->Unit(benchmark::kMillisecond);

void BM_RowSums(benchmark::State& state) {
    const SparseMatrix& f = cubeMatrix();
    for (auto _ : state)
        benchmark::DoNotOptimize(rowSums(f));
    setNonzeroRate(state, f);
}
BENCHMARK(BM_RowSums)->Unit(benchmark::kMillisecond);

void BM_Transpose(benchmark::State& state) {
    const SparseMatrix& f = cubeMatrix();
    for (auto _ : state)
        benchmark::DoNotOptimize(transpose(f));
    setNonzeroRate(state, f);
}
BENCHMARK(BM_Transpose)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace daisy
