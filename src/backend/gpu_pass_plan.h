#pragma once
// The GPU backends' pass strategy and launch sizing, written once for vulkan and cuda and free
// of either API's types, so the host side is tested without a device
// (tests/backend/gpu_pass_plan_test.cpp, tests/cuda/pair_slot_test.cpp).
//
// A GPU backend runs the shared pair kernel (shared/pair_kernel.h, pairEntryInMode) in one of
// three passes over a list of pairs (DAISY_PAIR_MODE_*, shared/config.h): the unoccluded factors,
// V_ij alone, or the hybrid factors without the adaptive refinement. GpuPassEvaluator turns those
// passes into the driver's PairEvaluator (radiosity/pair_evaluator.h):
//   - pairs with rays: V_ij first, then the factors only for the pairs some segment reaches, and
//     F = factor * V in float (as pairEntry rounds it); the others are 0;
//   - the factors of the hybrid method: the far-field pass over every pair, then the whole kernel
//     again for the pairs it marks DAISY_FF_NEEDS_NEAR_CELLS; the other methods in one pass.
// The result equals pairEntry on every pair, bit for bit (shared/pair_kernel.h says why), so a
// GPU backend's matrix equals the reference backend's. A device that runs every branch masked
// (lavapipe) pays for the quadrature only where a ray gets through, and for the refinement only
// where a cell is near.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/expected.h"
#include "radiosity/form_factors.h"
#include "radiosity/pair_evaluator.h"
#include "shared/gpu_types.h"

namespace daisy {

// What a GPU backend provides: one pass of its pair kernel.
class PairKernelPasses {
public:
    virtual ~PairKernelPasses() = default;
    // out[k] = pairEntryInMode(mode, ...) of pairs[k] (shared/pair_kernel.h) with `rays` shadow
    // segments (used by DAISY_PAIR_MODE_VISIBILITY only; the factor passes get 0), for at most
    // the evaluator's batchPairs pairs; out.size() == pairs.size(). An error stops the build.
    virtual Expected<void> runPass(std::span<const shared::PairIndex> pairs, int mode, int rays,
                                   std::span<shared::PairFactors> out) = 0;
};

// Counts and times of a build's passes, for the backend's verbose log.
struct GpuPassStats {
    uint64_t tracedPairs = 0;  // pairs through the visibility pass
    uint64_t openPairs = 0;  // of those, with some segment through
    uint64_t factorPairs = 0;  // pairs whose factors were computed (clear and open)
    uint64_t nearPairs = 0;  // of those, rerun through the whole hybrid kernel
    double visibilitySeconds = 0;
    double factorSeconds = 0;
};

// What a shadow segment costs the cost model (PairEvaluator::segmentNs) on a GPU: next to
// nothing of a CPU thread's time; and on a device that is the CPU itself (Mesa's lavapipe, about
// 1.1 us a segment measured on the reference machine, docs/performance.md).
inline constexpr double kGpuSegmentNs = 10;
inline constexpr double kCpuDeviceSegmentNs = 1100;

// The pass strategy above as the driver's PairEvaluator, over `passes`, for the DAISY_METHOD_*
// constant `method` (kernelMethod, radiosity/kernel_inputs.h) and batches of at most
// `batchPairs` (>= 1) pairs; `segmentNs` is the device's price of a segment (above).
class GpuPassEvaluator final : public PairEvaluator {
public:
    GpuPassEvaluator(std::string name, std::size_t batchPairs, int method, PairKernelPasses& passes,
                     double segmentNs = kGpuSegmentNs);

    std::string name() const override { return name_; }
    std::size_t batchPairs() const override { return batchPairs_; }
    double segmentNs() const override { return segmentNs_; }
    Expected<void> evaluate(std::span<const shared::PairIndex> pairs, int rays,
                            std::span<shared::PairFactors> out) override;

    const GpuPassStats& stats() const { return stats_; }
    // One line on the passes so far, for logVerbose.
    std::string summary() const;

private:
    // The unoccluded factors of pairs into out (the far-field pass first for hybrid).
    Expected<void> factors(std::span<const shared::PairIndex> pairs,
                           std::span<shared::PairFactors> out);

    std::string name_;
    std::size_t batchPairs_;
    int method_;
    PairKernelPasses& passes_;
    double segmentNs_;
    GpuPassStats stats_;
    // Scratch reused across batches: a pass's subset of pairs, where each came from, results.
    std::vector<shared::PairIndex> open_, near_;
    std::vector<uint32_t> openSlot_, nearSlot_;
    std::vector<shared::PairFactors> visibility_, openFactors_, nearFactors_;
};

// Estimated work of one pair for sizing GPU launches: its shadow segments plus its quadrature
// points (4^L on the smaller patch; 1 for nusselt).
uint64_t pairWork(const FormFactorSettings& settings);

// Pairs one launch (dispatch) may hold so that it does at most `workLimit` units of pairWork
// each: whole groups of `groupSize` threads, at least one group, however heavy the pairs. Sized
// so that a display watchdog never sees a long launch.
uint64_t launchPairsForWork(uint64_t workLimit, uint64_t pairWork, uint64_t groupSize);

}  // namespace daisy
