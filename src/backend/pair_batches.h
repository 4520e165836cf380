#pragma once
// The host side of the pair-kernel backends (reference, vulkan, later cuda): they evaluate the
// shared per-pair kernel (shared/pair_kernel.h) over batches of unordered pairs, and the one
// form-factor driver (radiosity/form_factors.h) does everything around it, for them exactly as
// for the cpu backend: the candidate pass, facing away, clear and covered shafts and the cost
// model, the CSR assembly and the memory checks. Only the pairs that need the kernel reach it:
// clear-shaft pairs with rays = 0, the rest with the K rays.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "radiosity/form_factors.h"
#include "shared/gpu_types.h"

namespace daisy {

// Evaluates pairs[k] into out[k] (out.size() == pairs.size()) with `rays` shadow segments a
// pair (0: unoccluded); an error stops the build. Called from one thread at a time.
using PairKernelBatch = std::function<Expected<void>(std::span<const shared::PairIndex> pairs,
                                                     int rays, std::span<shared::PairFactors> out)>;

// The patches as the kernels see them (float corners, normal and area from the double mesh).
std::vector<shared::PatchGeometry> kernelPatches(const PatchMesh& mesh);

// Estimated work of one pair for sizing GPU launches: its shadow segments plus its quadrature
// points (4^L on the smaller patch; 1 for nusselt).
uint64_t pairWork(const FormFactorSettings& settings);

// Builds F with the driver, the kernel evaluating batches of at most batchPairs pairs (sized for
// the device). Only riemann, nusselt and hybrid are pair methods; stochastic is refused with a
// message naming the backend (`backendName`).
Expected<FormFactorResult> buildFromPairBatches(const PatchMesh& mesh,
                                                const FormFactorSettings& settings,
                                                const char* backendName, std::size_t batchPairs,
                                                const PairKernelBatch& evaluate);

}  // namespace daisy
