// The CUDA kernel's per-thread code (evaluatePairSlot, cuda/pair_slot.h) and the host's argument
// packing (packPairKernelParams, cuda/batch_plan.h), run on the CPU over host arrays through the
// cuda backend's launch schedule (runDoubleBuffered and chunkRange, two slots of a few pairs):
// the matrix must equal the reference backend's bit for bit, since both evaluate the shared
// pairEntry on the same pairs and samples with the same compiler. What it cannot check without a
// device is only the CUDA calls themselves (copies, launches, streams).
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "backend/backend.h"
#include "backend/pair_batches.h"
#include "cuda/batch_plan.h"
#include "cuda/double_buffer.h"
#include "cuda/pair_slot.h"
#include "raycast/flat_bvh.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

using shared::PairFactors;
using shared::PairIndex;
using shared::PairKernelParams;

// F built as the cuda backend builds it, with the "device" being this CPU: launches of
// launchPairs pairs in two slots, each "launch" run at submit, unpacked at finish.
SparseMatrix buildLikeCuda(const PatchMesh& mesh, const FormFactorSettings& settings,
                           std::size_t launchPairs, std::size_t batchPairs) {
    const std::vector<shared::PatchGeometry> patches = kernelPatches(mesh);
    const FlatBvh bvh = buildFlatBvh(mesh).value();
    const PairKernelParams params =
        packPairKernelParams(settings, patches.data(), bvh.nodes.data(), bvh.triangles.data());
    std::vector<PairIndex> slotPairs[2];
    std::vector<PairFactors> slotResults[2];
    for (int s = 0; s < 2; ++s) {
        slotPairs[s].resize(launchPairs);
        slotResults[s].resize(launchPairs);
    }
    const PairKernelBatch evaluate = [&](std::span<const PairIndex> pairs, int rays,
                                         std::span<PairFactors> out) -> Expected<void> {
        const auto submit = [&](int s, std::size_t chunk) -> Expected<void> {
            const ChunkRange range = chunkRange(chunk, launchPairs, pairs.size());
            std::memcpy(slotPairs[s].data(), pairs.data() + range.first,
                        range.count * sizeof(PairIndex));
            PairKernelParams launch = params;
            launch.pairs = reinterpret_cast<uint64_t>(slotPairs[s].data());
            launch.results = reinterpret_cast<uint64_t>(slotResults[s].data());
            launch.pairCount = uint32_t(range.count);
            launch.rays = rays;
            for (uint32_t k = 0; k < launch.pairCount; ++k)
                evaluatePairSlot(launch, k);
            return {};
        };
        const auto finish = [&](int s, std::size_t chunk) -> Expected<void> {
            const ChunkRange range = chunkRange(chunk, launchPairs, pairs.size());
            std::memcpy(out.data() + range.first, slotResults[s].data(),
                        range.count * sizeof(PairFactors));
            return {};
        };
        return runDoubleBuffered(chunkCount(pairs.size(), launchPairs), submit, finish);
    };
    auto result = buildFromPairBatches(mesh, settings, "cuda", batchPairs, evaluate);
    EXPECT_TRUE(result.ok()) << result.error().message;
    return result.ok() ? std::move(result->matrix) : SparseMatrix{};
}

TEST(CudaPairSlot, HostPipelineOnTheCpuEqualsTheReferenceBackend) {
    const PatchMesh mesh = verify::patchesOf(verify::halfOccludedSquares());
    const std::unique_ptr<Backend> reference = makeReferenceBackend();
    for (FormFactorMethod method :
         {FormFactorMethod::Hybrid, FormFactorMethod::Riemann, FormFactorMethod::Nusselt}) {
        for (int rays : {0, 16}) {
            SCOPED_TRACE(std::string(formFactorMethodName(method)) + " rays " +
                         std::to_string(rays));
            FormFactorSettings settings;
            settings.method = method;
            settings.raysPerPair = rays;
            settings.seed = 12345;  // folded by packPairKernelParams as by the reference backend
            settings.progress = false;
            const SparseMatrix expected = reference->buildFormFactors(mesh, settings)->matrix;
            ASSERT_GT(expected.nonzeroCount(), 0u);
            for (const auto& [launch, batch] : {std::pair<std::size_t, std::size_t>{7, 20},
                                                std::pair<std::size_t, std::size_t>{64, 1000}}) {
                const SparseMatrix f = buildLikeCuda(mesh, settings, launch, batch);
                EXPECT_EQ(f.rowOffsets, expected.rowOffsets) << launch;
                EXPECT_EQ(f.columns, expected.columns) << launch;
                EXPECT_EQ(f.values, expected.values) << launch;
            }
        }
    }
}

// A launch's pairOffset shifts both the pair it reads and the result it writes.
TEST(CudaPairSlot, PairOffsetSelectsTheSlot) {
    const PatchMesh mesh = verify::patchesOf(verify::parallelSquares(1));
    const std::vector<shared::PatchGeometry> patches = kernelPatches(mesh);
    const FlatBvh bvh = buildFlatBvh(mesh).value();
    FormFactorSettings settings;
    PairKernelParams params =
        packPairKernelParams(settings, patches.data(), bvh.nodes.data(), bvh.triangles.data());
    // Patches 0, 1 on one square, 2, 3 on the other, facing it.
    const std::vector<PairIndex> pairs = {{0, 1}, {0, 2}, {1, 3}};
    std::vector<PairFactors> results(3, PairFactors{-1.0f, -1.0f});
    params.pairs = reinterpret_cast<uint64_t>(pairs.data());
    params.results = reinterpret_cast<uint64_t>(results.data());
    params.pairOffset = 1;
    params.pairCount = 2;
    params.rays = 0;
    evaluatePairSlot(params, 1);  // slot 2: the pair (1, 3)
    EXPECT_EQ(results[0].fij, -1.0f);
    EXPECT_EQ(results[1].fij, -1.0f);
    const PairFactors direct = shared::pairEntry(
        1, 3, patches[1], patches[3], params.method, params.level, 0, params.seed, params.clearance,
        shared::BvhNodeBuffer{bvh.nodes.data()}, shared::BvhTriangleBuffer{bvh.triangles.data()});
    EXPECT_GT(direct.fij, 0.0f);
    EXPECT_EQ(results[2].fij, direct.fij);
    EXPECT_EQ(results[2].fji, direct.fji);
}

}  // namespace
}  // namespace daisy
