// The CUDA kernel's per-thread code (evaluatePairSlot, cuda/pair_slot.h) and the host's argument
// packing (packPairKernelParams, cuda/batch_plan.h), run on the CPU over host arrays through the
// cuda backend's launch schedule (runDoubleBuffered and chunkRange, two slots of a few pairs) and
// the shared GPU pass strategy (backend/gpu_pass_plan.h: visibility, far field, near cells): the
// matrix must equal the reference backend's bit for bit, since both evaluate the shared kernel
// (pairEntry, or its passes, equal to it by construction) on the same pairs and samples with
// the same compiler. What it cannot check without a
// device is only the CUDA calls themselves (copies, launches, streams).
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "backend/backend.h"
#include "backend/gpu_pass_plan.h"
#include "cuda/batch_plan.h"
#include "cuda/double_buffer.h"
#include "cuda/pair_slot.h"
#include "radiosity/kernel_inputs.h"
#include "raycast/flat_bvh.h"
#include "shared/config.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

using shared::PairFactors;
using shared::PairIndex;
using shared::PairKernelParams;

// The cuda backend's passes with the "device" being this CPU: launches of launchPairs pairs in
// two slots, each "launch" run at submit, unpacked at finish.
class HostPasses final : public PairKernelPasses {
public:
    HostPasses(const PairKernelParams& params, std::size_t launchPairs)
        : params_(params), launchPairs_(launchPairs) {
        for (int s = 0; s < 2; ++s) {
            slotPairs_[s].resize(launchPairs);
            slotResults_[s].resize(launchPairs);
        }
    }

    Expected<void> runPass(std::span<const PairIndex> pairs, int mode, int rays,
                           std::span<PairFactors> out) override {
        ++passes[mode];
        const auto submit = [&](int s, std::size_t chunk) -> Expected<void> {
            const ChunkRange range = chunkRange(chunk, launchPairs_, pairs.size());
            std::memcpy(slotPairs_[s].data(), pairs.data() + range.first,
                        range.count * sizeof(PairIndex));
            PairKernelParams launch = params_;
            launch.pairs = reinterpret_cast<uint64_t>(slotPairs_[s].data());
            launch.results = reinterpret_cast<uint64_t>(slotResults_[s].data());
            launch.pairCount = uint32_t(range.count);
            launch.rays = rays;
            for (uint32_t k = 0; k < launch.pairCount; ++k)
                evaluatePairSlot(launch, mode, k);
            return {};
        };
        const auto finish = [&](int s, std::size_t chunk) -> Expected<void> {
            const ChunkRange range = chunkRange(chunk, launchPairs_, pairs.size());
            std::memcpy(out.data() + range.first, slotResults_[s].data(),
                        range.count * sizeof(PairFactors));
            return {};
        };
        return runDoubleBuffered(chunkCount(pairs.size(), launchPairs_), submit, finish);
    }

    int passes[3] = {0, 0, 0};  // passes run, by DAISY_PAIR_MODE_*

private:
    PairKernelParams params_;
    std::size_t launchPairs_;
    std::vector<PairIndex> slotPairs_[2];
    std::vector<PairFactors> slotResults_[2];
};

// F built as the cuda backend builds it: the shared GPU pass strategy over HostPasses.
SparseMatrix buildLikeCuda(const PatchMesh& mesh, const FormFactorSettings& settings,
                           std::size_t launchPairs, std::size_t batchPairs) {
    const std::vector<shared::PatchGeometry> patches = kernelPatches(mesh);
    const FlatBvh bvh = buildFlatBvh(mesh).value();
    const PairKernelParams params =
        packPairKernelParams(settings, patches.data(), bvh.nodes.data(), bvh.triangles.data());
    HostPasses passes(params, launchPairs);
    GpuPassEvaluator evaluator("cuda", batchPairs, params.method, passes);
    auto result = computeFormFactors(mesh, settings, evaluator);
    EXPECT_TRUE(result.ok()) << result.error().message;
    // Hybrid runs the far-field pass, the others never; rays add the visibility pass.
    const bool hybrid = settings.method == FormFactorMethod::Hybrid;
    EXPECT_EQ(passes.passes[DAISY_PAIR_MODE_FAR_FIELD] > 0, hybrid);
    EXPECT_EQ(passes.passes[DAISY_PAIR_MODE_VISIBILITY] > 0, settings.raysPerPair > 0);
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
    evaluatePairSlot(params, DAISY_PAIR_MODE_FACTORS, 1);  // slot 2: the pair (1, 3)
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
