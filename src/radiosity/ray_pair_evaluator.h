#pragma once
// The cpu backend's pair evaluation for the form-factor driver: the CPU kernel
// (shared/formfactor.h) and a RayCaster's segment queries (raycast/ray_caster.h), one TBB
// task per chunk of pairs. F_ij = float(double(factor) * open / K), the factor computed only
// for pairs some ray reaches.
#include <memory>

#include "geometry/patch_mesh.h"
#include "radiosity/form_factors.h"
#include "radiosity/pair_evaluator.h"
#include "raycast/ray_caster.h"

namespace daisy {

std::unique_ptr<PairEvaluator> makeRayPairEvaluator(const PatchMesh& mesh,
                                                    const FormFactorSettings& settings,
                                                    const RayCaster& rays);

}  // namespace daisy
