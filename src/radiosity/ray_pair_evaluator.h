#pragma once
// The cpu backend's pair evaluation for the form-factor driver: the CPU kernel
// (shared/formfactor.h) and a RayCaster's segment queries (raycast/ray_caster.h), one TBB
// task per chunk of pairs. Both entries are the unoccluded factors (radiosity/hybrid_far_field.h,
// bit-identical to the shared kernel) times V (shared::kernelWeightedVisibility) in float, the
// factors computed only for pairs some segment reaches.
#include <memory>

#include "geometry/patch_mesh.h"
#include "radiosity/form_factors.h"
#include "radiosity/pair_evaluator.h"
#include "raycast/ray_caster.h"
#include "shared/config.h"

namespace daisy {

// The hybrid rule's near cells refine to `hybridTolerance` of each factor
// (shared::hybridPairFactorWithin): F's own accuracy unless a caller needs less.
std::unique_ptr<PairEvaluator> makeRayPairEvaluator(const PatchMesh& mesh,
                                                    const FormFactorSettings& settings,
                                                    const RayCaster& rays,
                                                    float hybridTolerance = DAISY_FF_REL_TOL);

}  // namespace daisy
