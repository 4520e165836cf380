// Micro-benchmarks of the view-factor build (Google Benchmark; not in ctest): the shared
// per-pair kernels (pairs/s), the sample generator, the ray caster's occlusion rays in each packet
// mode (rays/s), and the two BVH builds (the ray caster's scene, our flat BVH; patches/s) on the
// benchmark scene assets/scenes/blacklight_box.gltf. Run:
//   cmake --build build --target daisy_microbench && build/daisy_microbench
// Results and the commands are recorded in docs/performance.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <memory>
#include <random>
#include <vector>

#include "geometry/patch_mesh.h"
#include "radiosity/shaft.h"
#include "radiosity/visibility_samples.h"
#include "raycast/flat_bvh.h"
#include "raycast/ray_caster.h"
#include "scene/load_scene.h"
#include "shared/formfactor.h"
#include "shared/sampling.h"

namespace daisy {
namespace {

using shared::PatchGeometry;
using shared::vec3;

struct BenchScene {
    PatchMesh mesh;
    std::vector<PatchGeometry> geometry;
    std::vector<std::pair<uint32_t, uint32_t>> facingPairs;  // a fixed-seed sample
};

const BenchScene& benchScene() {
    static const std::unique_ptr<BenchScene> scene = [] {
        // The scene relative to this source file: tests/bench/ -> assets/scenes/.
        const std::string source = __FILE__;
        const std::string root = source.substr(0, source.rfind("/tests/bench/"));
        auto loaded = loadScene(root + "/assets/scenes/blacklight_box.gltf");
        if (!loaded) std::abort();
        auto result = std::make_unique<BenchScene>();
        result->mesh = std::move(*buildPatchMesh(loaded->mesh, 0));
        const PatchMesh& mesh = result->mesh;
        for (std::size_t p = 0; p < mesh.patchCount(); ++p) {
            const auto corner = [&](int k) {
                const Vec3d& v = mesh.positions[mesh.patches[p][k]];
                return vec3(float(v.x), float(v.y), float(v.z));
            };
            result->geometry.push_back(shared::makePatchGeometry(corner(0), corner(1), corner(2)));
        }
        std::mt19937 rng(7);
        std::uniform_int_distribution<uint32_t> pick(0, uint32_t(mesh.patchCount() - 1));
        while (result->facingPairs.size() < 4096) {
            const uint32_t i = pick(rng), j = pick(rng);
            if (i != j && !shared::facingAway(result->geometry[i], result->geometry[j])) {
                result->facingPairs.push_back({i, j});
            }
        }
        return result;
    }();
    return *scene;
}

void BM_FacingAway(benchmark::State& state) {
    const BenchScene& s = benchScene();
    std::size_t k = 0;
    for (auto _ : state) {
        const auto& [i, j] = s.facingPairs[k++ & 4095];
        benchmark::DoNotOptimize(shared::facingAway(s.geometry[i], s.geometry[j ^ 1]));
    }
    state.counters["pairs/s"] =
        benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_FacingAway);

void BM_PairFactors(benchmark::State& state) {
    const BenchScene& s = benchScene();
    const int method = static_cast<int>(state.range(0));
    const int level = static_cast<int>(state.range(1));
    std::size_t k = 0;
    for (auto _ : state) {
        const auto& [i, j] = s.facingPairs[k++ & 4095];
        benchmark::DoNotOptimize(shared::pairFactors(method, level, s.geometry[i], s.geometry[j]));
    }
    state.counters["pairs/s"] =
        benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PairFactors)
    ->ArgNames({"method", "L"})
    ->Args({DAISY_METHOD_RIEMANN, 1})
    ->Args({DAISY_METHOD_RIEMANN, 2})
    ->Args({DAISY_METHOD_NUSSELT, 0})
    ->Args({DAISY_METHOD_HYBRID, 0})
    ->Args({DAISY_METHOD_HYBRID, 1})
    ->Args({DAISY_METHOD_HYBRID, 2});

// Close pairs (centroids under twice the sum of the patches' radii apart, facing each other) of
// the Blender-style Cornell box, whose planes are flat only to the exporter's rounding: some are
// neighbours on one wall with F_ij near 1e-8, far under the hybrid rule's relative tolerance, which
// only DAISY_FF_ABS_TOL stops short of the cell cap.
void BM_PairFactorsBlenderClose(benchmark::State& state) {
    static const std::vector<std::pair<PatchGeometry, PatchGeometry>> pairs = [] {
        const std::string source = __FILE__;
        const std::string root = source.substr(0, source.rfind("/tests/bench/"));
        auto loaded = loadScene(root + "/assets/scenes/formfactor_family/blender_cornell.gltf");
        if (!loaded) std::abort();
        const PatchMesh mesh = std::move(*buildPatchMesh(loaded->mesh, 0));
        std::vector<PatchGeometry> geometry;
        std::vector<float> radius;
        for (std::size_t p = 0; p < mesh.patchCount(); ++p) {
            vec3 c[3];
            for (int k = 0; k < 3; ++k) {
                const Vec3d& v = mesh.positions[mesh.patches[p][k]];
                c[k] = vec3(float(v.x), float(v.y), float(v.z));
            }
            geometry.push_back(shared::makePatchGeometry(c[0], c[1], c[2]));
            const vec3 m = (c[0] + c[1] + c[2]) * (1.0f / 3.0f);
            radius.push_back(std::max({length(c[0] - m), length(c[1] - m), length(c[2] - m)}));
        }
        std::vector<std::pair<PatchGeometry, PatchGeometry>> close;
        for (std::size_t i = 0; i < geometry.size() && close.size() < 4096; i += 7) {
            for (std::size_t j = 0; j < geometry.size(); ++j) {
                const vec3 between =
                    shared::patchCentroid(geometry[j]) - shared::patchCentroid(geometry[i]);
                if (i != j && length(between) < 2 * (radius[i] + radius[j]) &&
                    !shared::facingAway(geometry[i], geometry[j]))
                    close.push_back({geometry[i], geometry[j]});
            }
        }
        return close;
    }();
    std::size_t k = 0;
    for (auto _ : state) {
        const auto& [i, j] = pairs[k++ % pairs.size()];
        benchmark::DoNotOptimize(shared::pairFactors(DAISY_METHOD_HYBRID, 1, i, j));
    }
    state.counters["pairs/s"] =
        benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PairFactorsBlenderClose);

// The driver's batched form: all 16 trimmed segments of a pair at once (per segment).
void BM_ShadowSegments16(benchmark::State& state) {
    const BenchScene& s = benchScene();
    std::size_t k = 0;
    SegmentArrays segments;
    segments.resize(16);
    float weights[16];
    for (auto _ : state) {
        const auto& [i, j] = s.facingPairs[k++ & 4095];
        shadowSegments(shared::pairSeed(i, j, 1u), 16, s.geometry[i], s.geometry[j], 1e-5f,
                       segments, 0, weights);
        benchmark::DoNotOptimize(segments.x0.data());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * 16);
}
BENCHMARK(BM_ShadowSegments16);

void BM_VisibilitySamplePair(benchmark::State& state) {
    const BenchScene& s = benchScene();
    std::size_t k = 0;
    for (auto _ : state) {
        const auto& [i, j] = s.facingPairs[(k >> 4) & 4095];
        vec3 pi, pj;
        shared::visibilitySamplePair(shared::pairSeed(i, j, 1u), int(k & 15), 16, s.geometry[i],
                                     s.geometry[j], pi, pj);
        benchmark::DoNotOptimize(pi);
        benchmark::DoNotOptimize(pj);
        ++k;
    }
}
BENCHMARK(BM_VisibilitySamplePair);

// Shaft builds between the parallelograms spanned by facing triangles (4 + 4 corners, the most
// common shaft of the pair loop: two-triangle nodes of tessellated faces), per shaft.
void BM_ShaftBuild(benchmark::State& state) {
    const BenchScene& s = benchScene();
    const auto quad = [&](uint32_t p) {
        const auto& t = s.mesh.patches[p];
        const Vec3d& a = s.mesh.positions[t[0]];
        const Vec3d& b = s.mesh.positions[t[1]];
        const Vec3d& c = s.mesh.positions[t[2]];
        return std::array<Vec3d, 4>{a, b, b + c - a, c};
    };
    std::vector<std::array<Vec3d, 4>> quads(s.mesh.patchCount());
    for (uint32_t p = 0; p < quads.size(); ++p)
        quads[p] = quad(p);
    Shaft shaft;
    std::size_t k = 0;
    for (auto _ : state) {
        const auto& [i, j] = s.facingPairs[k++ & 4095];
        benchmark::DoNotOptimize(shaft.build(quads[i], quads[j], 1e-6));
    }
    state.counters["shafts/s"] =
        benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ShaftBuild);

// Occlusion segments of 16 samples for each of 4096 random facing pairs (more of them blocked
// than in the driver, which traces only pairs shaft culling could not settle), per packet mode.
void BM_RayCasterOccluded(benchmark::State& state) {
    const BenchScene& s = benchScene();
    const auto mode = static_cast<PacketMode>(state.range(0));
    static std::unique_ptr<RayCaster> caster = std::move(makeRayCaster(s.mesh).value());
    caster->setPacketMode(mode);
    SegmentArrays segments;
    segments.resize(s.facingPairs.size() * 16);
    std::vector<float> weights(segments.size());
    for (std::size_t p = 0; p < s.facingPairs.size(); ++p) {
        const auto& [i, j] = s.facingPairs[p];
        shadowSegments(shared::pairSeed(i, j, 1u), 16, s.geometry[i], s.geometry[j], 1e-5f,
                       segments, 16 * p, weights.data() + 16 * p);
    }
    std::vector<uint8_t> blocked(segments.size());
    for (auto _ : state) {
        caster->occluded(segments, blocked);
        benchmark::DoNotOptimize(blocked.data());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(segments.size()));
    state.counters["rays/s"] = benchmark::Counter(
        double(state.iterations()) * double(segments.size()), benchmark::Counter::kIsRate);
    state.SetLabel(packetModeName(mode));
}
BENCHMARK(BM_RayCasterOccluded)
    ->Arg(int(PacketMode::Single))
    ->Arg(int(PacketMode::Packet4))
    ->Arg(int(PacketMode::Packet8))
    ->Arg(int(PacketMode::Packet16))
    ->Arg(int(PacketMode::Stream))
    ->Unit(benchmark::kMillisecond);

// The ray caster's scene build (a high-quality BVH) of the whole scene, one thread pool.
void BM_RayCasterBuild(benchmark::State& state) {
    const BenchScene& s = benchScene();
    for (auto _ : state) {
        auto caster = makeRayCaster(s.mesh);
        if (!caster) {
            state.SkipWithError(caster.error().message.c_str());
            return;
        }
        benchmark::DoNotOptimize(caster->get());
    }
    state.counters["patches/s"] = benchmark::Counter(
        double(state.iterations()) * double(s.mesh.patchCount()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RayCasterBuild)->Unit(benchmark::kMillisecond)->UseRealTime();

// The flat BVH of the reference and GPU backends (raycast/flat_bvh.h): build and flatten.
void BM_FlatBvhBuild(benchmark::State& state) {
    const BenchScene& s = benchScene();
    for (auto _ : state) {
        auto bvh = buildFlatBvh(s.mesh);
        if (!bvh) {
            state.SkipWithError(bvh.error().message.c_str());
            return;
        }
        benchmark::DoNotOptimize(bvh->nodes.data());
    }
    state.counters["patches/s"] = benchmark::Counter(
        double(state.iterations()) * double(s.mesh.patchCount()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_FlatBvhBuild)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace daisy
