// The GPU pass strategy and launch sizing (backend/gpu_pass_plan.h), without a device: a fake
// kernel whose passes return chosen values shows which pairs each pass sees and how the results
// combine (the strategy's documented order); the launch sizes are its formulas worked by hand.
// That the strategy's matrix equals the reference backend's bit for bit is tested with the real
// kernel in tests/cuda/pair_slot_test.cpp and tests/vulkan/vulkan_backend_test.cpp.
#include "backend/gpu_pass_plan.h"

#include <gtest/gtest.h>

#include <vector>

#include "shared/config.h"

namespace daisy {
namespace {

using shared::PairFactors;
using shared::PairIndex;

// Pair (i, j): V = 0 when i is even, else 0.5; the far field marks pairs with j == 3 as needing
// the near cells; the factors are (i + j) / 100 and their half, the far field's the same.
struct FakePasses final : PairKernelPasses {
    struct Call {
        int mode;
        int rays;
        std::vector<PairIndex> pairs;
    };
    std::vector<Call> calls;

    Expected<void> runPass(std::span<const PairIndex> pairs, int mode, int rays,
                           std::span<PairFactors> out) override {
        calls.push_back({mode, rays, {pairs.begin(), pairs.end()}});
        for (std::size_t k = 0; k < pairs.size(); ++k) {
            const float f = float(pairs[k].i + pairs[k].j) / 100.0f;
            if (mode == DAISY_PAIR_MODE_VISIBILITY) {
                const float v = pairs[k].i % 2 == 0 ? 0.0f : 0.5f;
                out[k] = PairFactors{v, v};
            } else if (mode == DAISY_PAIR_MODE_FAR_FIELD && pairs[k].j == 3) {
                out[k] = PairFactors{DAISY_FF_NEEDS_NEAR_CELLS, DAISY_FF_NEEDS_NEAR_CELLS};
            } else {
                out[k] = PairFactors{f, f / 2.0f};
            }
        }
        return {};
    }
};

bool samePairs(const std::vector<PairIndex>& a, const std::vector<PairIndex>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t k = 0; k < a.size(); ++k) {
        if (a[k].i != b[k].i || a[k].j != b[k].j) return false;
    }
    return true;
}

TEST(GpuPassPlan, HybridWithRaysTracesThenFarFieldThenNearCells) {
    FakePasses passes;
    GpuPassEvaluator evaluator("fake", 16, DAISY_METHOD_HYBRID, passes);
    const std::vector<PairIndex> pairs = {{0, 1}, {1, 2}, {1, 3}, {2, 3}, {3, 4}};
    std::vector<PairFactors> out(pairs.size(), PairFactors{-2.0f, -2.0f});
    ASSERT_TRUE(evaluator.evaluate(pairs, 8, out).ok());
    ASSERT_EQ(passes.calls.size(), 3u);
    EXPECT_EQ(passes.calls[0].mode, DAISY_PAIR_MODE_VISIBILITY);
    EXPECT_EQ(passes.calls[0].rays, 8);
    EXPECT_TRUE(samePairs(passes.calls[0].pairs, pairs));
    // The open pairs (odd i) through the far field, then the one it marked.
    EXPECT_EQ(passes.calls[1].mode, DAISY_PAIR_MODE_FAR_FIELD);
    EXPECT_EQ(passes.calls[1].rays, 0);
    EXPECT_TRUE(samePairs(passes.calls[1].pairs, {{1, 2}, {1, 3}, {3, 4}}));
    EXPECT_EQ(passes.calls[2].mode, DAISY_PAIR_MODE_FACTORS);
    EXPECT_TRUE(samePairs(passes.calls[2].pairs, {{1, 3}}));
    // Blocked pairs are 0; open ones factor * V, in float.
    EXPECT_EQ(out[0].fij, 0.0f);
    EXPECT_EQ(out[3].fji, 0.0f);
    EXPECT_EQ(out[1].fij, (3.0f / 100.0f) * 0.5f);
    EXPECT_EQ(out[2].fij, (4.0f / 100.0f) * 0.5f);
    EXPECT_EQ(out[2].fji, (4.0f / 100.0f / 2.0f) * 0.5f);
    EXPECT_EQ(evaluator.stats().tracedPairs, 5u);
    EXPECT_EQ(evaluator.stats().openPairs, 3u);
    EXPECT_EQ(evaluator.stats().factorPairs, 3u);
    EXPECT_EQ(evaluator.stats().nearPairs, 1u);
}

TEST(GpuPassPlan, OtherMethodsAndClearPairsSkipThePassesTheyDoNotNeed) {
    FakePasses passes;
    GpuPassEvaluator evaluator("fake", 16, DAISY_METHOD_RIEMANN, passes);
    const std::vector<PairIndex> pairs = {{0, 3}, {1, 3}};
    std::vector<PairFactors> out(pairs.size());
    ASSERT_TRUE(evaluator.evaluate(pairs, 0, out).ok());
    ASSERT_EQ(passes.calls.size(), 1u);
    EXPECT_EQ(passes.calls[0].mode, DAISY_PAIR_MODE_FACTORS);
    EXPECT_EQ(out[1].fij, 4.0f / 100.0f);
    // Every traced pair blocked: no factor pass at all.
    passes.calls.clear();
    const std::vector<PairIndex> blocked = {{0, 1}, {2, 5}};
    ASSERT_TRUE(evaluator.evaluate(blocked, 4, out).ok());
    ASSERT_EQ(passes.calls.size(), 1u);
    EXPECT_EQ(passes.calls[0].mode, DAISY_PAIR_MODE_VISIBILITY);
    EXPECT_EQ(out[0].fij, 0.0f);
    EXPECT_EQ(out[1].fji, 0.0f);
}

TEST(GpuPassPlan, BatchesAreAtLeastOnePair) {
    FakePasses passes;
    EXPECT_EQ(GpuPassEvaluator("fake", 0, DAISY_METHOD_HYBRID, passes).batchPairs(), 1u);
    EXPECT_EQ(GpuPassEvaluator("fake", 1000, DAISY_METHOD_HYBRID, passes).batchPairs(), 1000u);
}

// pairWork: K segments plus 4^L quadrature points (1 for nusselt).
TEST(GpuPassPlan, PairWorkAndLaunchSizes) {
    FormFactorSettings settings;
    settings.raysPerPair = 16;
    settings.quadratureLevel = 2;
    EXPECT_EQ(pairWork(settings), 16u + 16u);
    settings.method = FormFactorMethod::Nusselt;
    EXPECT_EQ(pairWork(settings), 17u);
    // 2^22 units / 32 a pair = 131072 pairs, whole groups of 64.
    EXPECT_EQ(launchPairsForWork(uint64_t(1) << 22, 32, 64), 131072u);
    // 2^24 / 4112 = 4080 pairs: 63 whole groups.
    EXPECT_EQ(launchPairsForWork(uint64_t(1) << 24, 4096 + 16, 64), 63u * 64);
    // Pairs heavier than the whole limit still get one group.
    EXPECT_EQ(launchPairsForWork(1000, uint64_t(1) << 30, 64), 64u);
}

}  // namespace
}  // namespace daisy
