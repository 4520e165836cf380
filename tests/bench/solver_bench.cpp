// Micro-benchmarks of the radiosity solvers (Google Benchmark; not in ctest) on the benchmark
// scene assets/scenes/blacklight_box.gltf (7,712 patches) with 16 wavelength samples
// (360:660:20) and its fluorescent posters, solved to 1e-4. F is read from a Matrix Market file
// made once by
//   daisy formfactors assets/scenes/blacklight_box.gltf -o /tmp/solve_blacklight_F.mtx
// (path overridable with DAISY_SOLVER_BENCH_MATRIX; the benchmarks skip without it). Run:
//   cmake --build build --target daisy_microbench &&
//   build/daisy_microbench --benchmark_filter=Solve --benchmark_min_time=2
// Results and the commands are recorded in docs/performance.md.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>
#include <string>

#include "geometry/patch_mesh.h"
#include "radiosity/matrix_market.h"
#include "radiosity/radiosity_system.h"
#include "radiosity/solver.h"
#include "scene/load_scene.h"
#include "spectral/wavelength_set.h"
#include "spectral/wavelength_spec.h"

namespace daisy {
namespace {

struct SolverBenchData {
    SparseMatrix formFactors;
    RadiositySystem system;
};

const SolverBenchData* benchData() {
    static const std::unique_ptr<SolverBenchData> data = []() -> std::unique_ptr<SolverBenchData> {
        const char* override = std::getenv("DAISY_SOLVER_BENCH_MATRIX");
        const std::string matrixPath = override ? override : "/tmp/solve_blacklight_F.mtx";
        const std::string source = __FILE__;
        const std::string root = source.substr(0, source.rfind("/tests/bench/"));
        auto scene = loadScene(root + "/assets/scenes/blacklight_box.gltf");
        if (!scene) return nullptr;
        auto patches = buildPatchMesh(scene->mesh, 0);
        auto spec = parseWavelengthSpec("360:660:20");
        if (!patches || !spec) return nullptr;
        auto set = makeWavelengthSet(*spec);
        if (!set) return nullptr;
        auto system = buildRadiositySystem(*scene, *patches, *set);
        auto matrix = readMatrixMarket(matrixPath);
        if (!system || !matrix || matrix->size != system->patchCount) return nullptr;
        return std::make_unique<SolverBenchData>(
            SolverBenchData{std::move(*matrix), std::move(*system)});
    }();
    return data.get();
}

void solveBench(benchmark::State& state, SolverKind kind) {
    const SolverBenchData* data = benchData();
    if (!data) {
        state.SkipWithError("no blacklight_box matrix (see the file comment)");
        return;
    }
    SolverSettings settings;
    settings.kind = kind;
    settings.tolerance = 1e-4;
    settings.threads = static_cast<int>(state.range(0));
    SolverResult last;
    for (auto _ : state) {
        auto result = solveRadiosity(data->formFactors, data->system, settings);
        if (!result) {
            state.SkipWithError(result.error().message.c_str());
            return;
        }
        last = std::move(*result);
    }
    state.counters["iterations"] = last.iterations;
    state.counters["residual"] = last.residual;
    state.counters["ms_per_iteration"] = 1e3 * last.seconds / std::max(1, last.iterations);
    state.counters["nonzeros"] = double(data->formFactors.nonzeroCount());
    // One gather per iteration (plus the final residual's): stored entries read per second.
    state.counters["nonzeros/s"] =
        benchmark::Counter(double(state.iterations()) * double(last.iterations + 1) *
                               double(data->formFactors.nonzeroCount()),
                           benchmark::Counter::kIsRate);
}

void BM_SolveGaussSeidel(benchmark::State& state) {
    solveBench(state, SolverKind::GaussSeidel);
}
void BM_SolveJacobi(benchmark::State& state) {
    solveBench(state, SolverKind::Jacobi);
}
void BM_SolveSouthwell(benchmark::State& state) {
    solveBench(state, SolverKind::Southwell);
}
BENCHMARK(BM_SolveGaussSeidel)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SolveJacobi)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SolveSouthwell)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace daisy
