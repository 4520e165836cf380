#pragma once
// The host side of the pair-kernel backends (reference, vulkan, later cuda): they evaluate the
// shared per-pair kernel (shared/pair_kernel.h) over lists of unordered pairs, and this driver
// does everything around it. It enumerates the candidate pairs (i < j, not shared::facingAway)
// in row order, hands them to the backend in batches, and assembles F in CSR: each pair's F_ij
// in row i and F_ji in row j, columns ascending, stored zeros dropped; a counting pass sizes
// every row first, so memory is the CSR plus one batch, never triplets. Refuses builds over
// settings.maxMemoryBytes before allocating (same estimate as the cpu driver).
#include <cstddef>
#include <functional>
#include <span>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "radiosity/form_factors.h"
#include "shared/gpu_types.h"

namespace daisy {

// Evaluates pairs[k] into out[k] (out.size() == pairs.size()); an error stops the build.
using PairEvaluator = std::function<Expected<void>(std::span<const shared::PairIndex> pairs,
                                                   std::span<shared::PairFactors> out)>;

// The kernel-side inputs every pair-kernel backend uploads: the patches as the kernels see them
// and the end clearance of shadow segments (scene units). The method constant and the 32-bit
// seed come from detail::methodConstant and detail::seed32 (radiosity/form_factors_internal.h),
// as in the cpu backend.
std::vector<shared::PatchGeometry> kernelPatches(const PatchMesh& mesh);
float shadowClearance(const PatchMesh& mesh);

// Builds F from batches of at most batchPairs pairs. Only riemann, nusselt and hybrid are pair
// methods; stochastic is refused with a message naming the backend (`backendName`).
Expected<FormFactorResult> buildFromPairBatches(const PatchMesh& mesh,
                                                const FormFactorSettings& settings,
                                                const char* backendName, std::size_t batchPairs,
                                                const PairEvaluator& evaluate);

}  // namespace daisy
