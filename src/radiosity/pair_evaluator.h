#pragma once
// The one thing a backend does in the form-factor driver (radiosity/form_factors.h, DESIGN.md
// section 3): evaluate a batch of unordered pairs, kernel and rays. The driver does everything
// else for every backend alike: the candidate pass, the decisions that need no rays (facing
// away, clear shaft, covered, and the cost model that decides whether culling pays), the CSR
// assembly and the memory checks. The cpu backend evaluates with the CPU kernel and rays
// (radiosity/ray_pair_evaluator.h); reference, vulkan (and cuda next) with the shared pair kernel
// (shared/pair_kernel.h) through backend/pair_batches.h.
#include <cstddef>
#include <span>
#include <string>

#include "core/expected.h"
#include "shared/gpu_types.h"

namespace daisy {

// Shadow segments stop pairClearance(kEndClearanceRelative, i, j) (shared/visibility.h) short
// of their patches' planes: a few float roundings of the two patches' coordinates, so the end
// patches never report themselves as blockers. Every backend passes this one constant.
inline constexpr float kEndClearanceRelative = 2e-6f;

class PairEvaluator {
public:
    virtual ~PairEvaluator() = default;
    // The backend's name, for messages.
    virtual std::string name() const = 0;
    // The most pairs one evaluate() call takes (sized for the device's buffers); >= 1.
    virtual std::size_t batchPairs() const = 0;
    // fij[k] = F_ij of pairs[k] (i < j, a candidate pair: not facing away): the unoccluded
    // factor (shared/formfactor.h, negative rounding clamped to 0) times the kernel-weighted
    // unblocked share of `rays` shadow segments (shared::kernelWeightedVisibility, in float);
    // rays == 0: the unoccluded factor alone.
    // fij.size() == pairs.size() <= batchPairs(). Called from one thread at a time (it may run
    // in parallel inside); an error stops the build.
    virtual Expected<void> evaluate(std::span<const shared::PairIndex> pairs, int rays,
                                    std::span<float> fij) = 0;
};

}  // namespace daisy
