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

namespace daisy {
namespace {

void addGrid(TriangleMesh& mesh, Vec3d origin, Vec3d u, Vec3d v, int n) {
    const auto base = static_cast<uint32_t>(mesh.positions.size());
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x)
            mesh.positions.push_back(origin + u * (double(x) / n) + v * (double(y) / n));
    const auto at = [&](int x, int y) { return base + uint32_t(y * (n + 1) + x); };
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            mesh.triangles.push_back({at(x, y), at(x + 1, y), at(x + 1, y + 1)});
            mesh.triangles.push_back({at(x, y), at(x + 1, y + 1), at(x, y + 1)});
            mesh.materials.insert(mesh.materials.end(), {0u, 0u});
        }
    }
}

const SparseMatrix& cubeMatrix() {
    static const std::unique_ptr<SparseMatrix> matrix = [] {
        const int n = 14;
        TriangleMesh mesh;
        const Vec3d o{0, 0, 0}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
        addGrid(mesh, o, x, y, n);
        addGrid(mesh, z, y, x, n);
        addGrid(mesh, o, z, x, n);
        addGrid(mesh, y, x, z, n);
        addGrid(mesh, o, y, z, n);
        addGrid(mesh, x, z, y, n);
        auto patches = buildPatchMesh(mesh, 0);
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
BENCHMARK(BM_AccumulateDouble)->ArgName("m")->Arg(1)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AccumulateFloat)->ArgName("m")->Arg(1)->Arg(16)->Unit(benchmark::kMillisecond);

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
