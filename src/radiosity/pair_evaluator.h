#pragma once
// The one thing a backend does in the form-factor driver (radiosity/form_factors.h, DESIGN.md
// section 3): evaluate a batch of unordered pairs, kernel and rays, both directions. The driver
// does everything else for every backend alike: the candidate pass, the decisions that need no
// rays (facing away, clear shaft, covered, and the cost model that decides whether culling
// pays), the CSR assembly and the memory checks.
//
// Implementations: the cpu backend's (radiosity/ray_pair_evaluator.h: the CPU kernel and a
// RayCaster's segments); the reference backend's (the shared pair kernel, shared/pair_kernel.h,
// on the CPU); the GPU backends' (backend/gpu_pass_plan.h: the shared pass strategy over a
// device's kernel passes, run by vulkan and cuda). The inputs every one of them hands to the
// kernels are radiosity/kernel_inputs.h.
#include <cstddef>
#include <span>
#include <string>

#include "core/expected.h"
#include "shared/gpu_types.h"

namespace daisy {

class PairEvaluator {
public:
    virtual ~PairEvaluator() = default;
    // The backend's name, for messages.
    virtual std::string name() const = 0;
    // The most pairs one evaluate() call takes (sized for the device's buffers); >= 1.
    virtual std::size_t batchPairs() const = 0;
    // What one shadow segment costs, for the driver's cost model (form_factors_cost_model.cpp):
    // nanoseconds of one thread of the reference machine (docs/performance.md), the segment's
    // share of its pair's tracing included. A constant of the backend and its device, never a
    // timing of this build: the model's choices decide which pairs are traced, so they must not
    // follow the machine's load.
    virtual double segmentNs() const = 0;
    // out[k] = {F_ij, F_ji} of pairs[k] = (i, j), i < j, a candidate pair (not facing away):
    // the unoccluded factors (shared/formfactor.h, the accurate direction computed and the
    // other by reciprocity in float, negative rounding clamped to 0) times V_ij, the
    // kernel-weighted unblocked share of `rays` shadow segments (shared::kernelWeightedVisibility,
    // in float); rays == 0: the unoccluded factors alone. Both entries are 0 when no segment
    // gets through. out.size() == pairs.size() <= batchPairs(). Called from one thread at a
    // time (it may run in parallel inside); an error stops the build.
    virtual Expected<void> evaluate(std::span<const shared::PairIndex> pairs, int rays,
                                    std::span<shared::PairFactors> out) = 0;
};

}  // namespace daisy
