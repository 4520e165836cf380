#pragma once
// What every backend hands to the form-factor kernels (shared/formfactor.h, shared/visibility.h,
// shared/pair_kernel.h), so that the cpu, reference, vulkan and cuda backends evaluate the same
// function of (pair, settings) and their matrices can be compared entry by entry:
//
// - the patches as the kernels see them: float corners, with the normal and the area taken from
//   the double-precision mesh (kernelPatches), one PatchGeometry per patch in patch order;
// - the method as a DAISY_METHOD_* constant (kernelMethod) and the quadrature level L as given;
// - the 32-bit seed of every sample sequence, folded from the 64-bit --seed (kernelSeed);
// - the shadow segments' end clearance relative to the pair's size (kEndClearanceRelative).
//
// Pairs are unordered patch indices i < j (shared::PairIndex); results are shared::PairFactors,
// both directions of one evaluation. A backend that uploads these values (vulkan, cuda) uploads
// exactly these arrays and numbers; nothing else about the mesh reaches a kernel except the flat
// BVH (raycast/flat_bvh.h) or a RayCaster for the shadow segments.
#include <cstdint>
#include <vector>

#include "geometry/patch_mesh.h"
#include "radiosity/form_factors.h"
#include "shared/gpu_types.h"

namespace daisy {

// Shadow segments stop pairClearance(kEndClearanceRelative, i, j) (shared/visibility.h) short
// of their patches' planes: a few float roundings of the two patches' coordinates, so the end
// patches never report themselves as blockers. Every backend passes this one constant.
inline constexpr float kEndClearanceRelative = 2e-6f;

// The DAISY_METHOD_* constant (shared/config.h) the shared kernels take for `method`.
int kernelMethod(FormFactorMethod method);

// The 32-bit seed of the shared sample sequences (shared/rng.h) from the 64-bit --seed:
// pcgHash(low ^ pcgHash(high)).
uint32_t kernelSeed(uint64_t seed);

// The patches as the kernels see them: float corners from the mesh's positions, the normal and
// the area (m^2, scene units squared) rounded from the mesh's double values. Patch order.
std::vector<shared::PatchGeometry> kernelPatches(const PatchMesh& mesh);

// The scalar inputs of a build, as every pair-kernel backend passes them to shared::pairEntry.
struct KernelSettings {
    int method = 0;  // DAISY_METHOD_*
    int level = 0;  // quadrature level L (4^L cells a patch)
    uint32_t seed = 0;  // kernelSeed(settings.seed)
    float clearanceRelative = kEndClearanceRelative;
};

KernelSettings kernelSettings(const FormFactorSettings& settings);

}  // namespace daisy
