#pragma once
// The cpu backend's unoccluded pair factors (issue 18): shared::pairFactors (shared/formfactor.h)
// with the hybrid method's commonest cases done four points at a time. When no quadrature cell
// of i's clipped piece is near j (each is far, ratio >= DAISY_FF_FAR_RATIO: its centroid, or in
// the middle band from DAISY_FF_MID_RATIO: the three-point rule; at the default L = 1 most pairs
// of a room), the point-to-triangle factors are evaluated in SSE lanes by the same operations
// in the same order as the shared kernel, so the result is bit-identical to it (checked by
// tests/radiosity/hybrid_far_field_test.cpp). Points whose view of j must be clipped, pairs
// with a near cell, levels above 2 and the other methods are the shared kernel itself.
#include "shared/gpu_types.h"

namespace daisy {

// shared::hybridPairFactor(level, i, j), with its far and middle cells vectorised.
float hybridPairFactorCpu(int level, const shared::PatchGeometry& i,
                          const shared::PatchGeometry& j);

// shared::pairFactors(method, level, i, j), with hybridPairFactorCpu for the hybrid method.
shared::PairFactors pairFactorsCpu(int method, int level, const shared::PatchGeometry& i,
                                   const shared::PatchGeometry& j);

// pairFactorsCpu of a pair known not to face away (the driver's candidates, pair_evaluator.h):
// the same values without testing shared::facingAway again.
shared::PairFactors candidatePairFactorsCpu(int method, int level, const shared::PatchGeometry& i,
                                            const shared::PatchGeometry& j);

}  // namespace daisy
