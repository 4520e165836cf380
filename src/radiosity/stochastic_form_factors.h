#pragma once
// The stochastic method (DESIGN.md section 3, docs/formfactors.md): closest-hit rays per patch,
// not a per-pair kernel, so it runs outside the pair loop and its PairEvaluator.
// computeFormFactors (radiosity/form_factors.h) dispatches here with a RayCaster; the
// pair-kernel backends (reference, vulkan, cuda) refuse it.
#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "radiosity/form_factors.h"
#include "raycast/ray_caster.h"

namespace daisy::detail {

// F by the stochastic method, inside the caller's task arena. The rays start from the kernel
// inputs' patches and seed (radiosity/kernel_inputs.h), as every backend's kernels do.
Expected<FormFactorResult> computeStochastic(const PatchMesh& mesh,
                                             const FormFactorSettings& settings,
                                             const RayCaster& rays);

}  // namespace daisy::detail
