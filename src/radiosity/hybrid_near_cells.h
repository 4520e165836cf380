#pragma once
// The cpu backend's hybrid rule for a pair with near cells (shared::hybridPairFactorWithin with
// nearCells true): the same cells, the same refinement list and decisions, in the same order,
// with the point-to-triangle factors of each step evaluated together in SIMD lanes
// (pointToTriangleFactors, hybrid_far_field.h): the prologue's cells at once, then the children
// of every listed cell, then the 4 new cells of each split (48 points). Every value and every
// sum is the shared kernel's, so the result is bit-identical to it (checked by
// tests/radiosity/hybrid_far_field_test.cpp). Pairs that touch or nearly touch (a wall and the
// floor at their common edge, neighbours on a curved surface) are all such pairs: the near
// factors of the hierarchical transport and the matrix path's closest pairs.
#include "radiosity/hybrid_far_field.h"
#include "shared/gpu_types.h"

namespace daisy {

// shared::hybridPairFactorWithin(level, i, j, true, relativeTolerance), bit for bit.
float hybridNearPairFactor(int level, const shared::PatchGeometry& i,
                           const shared::PatchGeometry& j, float relativeTolerance,
                           FarFieldScratch& scratch);

}  // namespace daisy
