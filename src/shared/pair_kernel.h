// The per-pair kernel of the pair-kernel backends (reference, vulkan, cuda; DESIGN.md section 8):
// both entries of one unordered pair {i, j}, unoccluded factor times visibility. The host driver
// (radiosity/form_factors.h) enumerates the pairs and assembles F from what a backend's
// PairEvaluator returns (radiosity/pair_evaluator.h, inputs radiosity/kernel_inputs.h): the
// reference backend calls pairEntry once per pair; the GPU backends run pairEntryInMode in the
// passes of backend/gpu_pass_plan.h.
#ifndef DAISY_SHARED_PAIR_KERNEL_H
#define DAISY_SHARED_PAIR_KERNEL_H

#include "bvh_traverse.h"
#include "config.h"
#include "formfactor.h"
#include "gpu_types.h"
#include "prelude.h"
#include "rng.h"
#include "visibility.h"

DAISY_SHARED_BEGIN

// V_ij of the pair (i, j) (patch indices, i < j as the driver passes them) with geometry gi, gj:
// pairVisibility of `rays` (>= 1) shadow segments seeded by pairSeed(i, j, seed), end clearance
// pairClearance(clearanceRelative, gi, gj) (visibility.h).
DAISY_HD float pairEntryVisibility(uint i, uint j, DAISY_IN(PatchGeometry) gi,
                                   DAISY_IN(PatchGeometry) gj, int rays, uint seed,
                                   float clearanceRelative, BvhNodeBuffer nodes,
                                   BvhTriangleBuffer triangles) {
    float clearance = pairClearance(clearanceRelative, gi, gj);
    return pairVisibility(pairSeed(i, j, seed), rays, gi, gj, clearance, nodes, triangles);
}

// F_ij and F_ji of the pair (i, j) (patch indices, i < j as the driver passes them) with
// geometry gi, gj: pairFactors(method, level, gi, gj) (formfactor.h; negative rounding clamped to
// 0) times V_ij = pairVisibility of `rays` shadow segments seeded by pairSeed(i, j, seed)
// (visibility.h; the cpu backend's segments). V = 1 when rays == 0; no rays are cast when the
// unoccluded factor is 0 (facing-away pairs included). method is DAISY_METHOD_RIEMANN, _NUSSELT
// or _HYBRID (stochastic has no pair kernel: 0). seed is the 32-bit seed; the segments' end
// clearance is pairClearance(clearanceRelative, gi, gj) (visibility.h). fij * V is rounded once for
// power-of-two rays, as the cpu driver's float(double(fij) * open / K). A backend may compute
// the two factors apart (pairEntry with rays = 0 and pairEntryVisibility) and multiply them in
// float: the same result.
DAISY_HD PairFactors pairEntry(uint i, uint j, DAISY_IN(PatchGeometry) gi,
                               DAISY_IN(PatchGeometry) gj, int method, int level, int rays,
                               uint seed, float clearanceRelative, BvhNodeBuffer nodes,
                               BvhTriangleBuffer triangles) {
    PairFactors f = pairFactors(method, level, gi, gj);
    f.fij = max(0.0f, f.fij);
    f.fji = max(0.0f, f.fji);
    if (rays > 0 && (f.fij > 0.0f || f.fji > 0.0f)) {
        float v =
            pairEntryVisibility(i, j, gi, gj, rays, seed, clearanceRelative, nodes, triangles);
        f.fij = f.fij * v;
        f.fji = f.fji * v;
    }
    return f;
}

// pairEntry(i, j, gi, gj, DAISY_METHOD_HYBRID, level, 0, ...) without the hybrid rule's adaptive
// refinement (pairFactorsWith(..., false), formfactor.h): the same two factors, bit for bit, for
// a pair none of whose quadrature cells is near the other patch (most pairs of a room at the
// default level), and DAISY_FF_NEEDS_NEAR_CELLS in both entries for the others, which the caller
// then sends through pairEntry. On a device that runs every branch masked (lavapipe) the
// refinement's code costs every pair as much as a near pair's (docs/backends.md).
DAISY_HD PairFactors pairEntryFarField(DAISY_IN(PatchGeometry) gi, DAISY_IN(PatchGeometry) gj,
                                       int level) {
    PairFactors f = pairFactorsWith(DAISY_METHOD_HYBRID, level, gi, gj, false);
    if (f.fij != DAISY_FF_NEEDS_NEAR_CELLS) {
        f.fij = max(0.0f, f.fij);
        f.fji = max(0.0f, f.fji);
    }
    return f;
}

// One pass of the GPU pass strategy (backend/gpu_pass_plan.h) on the pair (i, j), by `mode`
// (DAISY_PAIR_MODE_*, config.h): VISIBILITY gives V_ij (pairEntryVisibility, `rays` >= 1) in
// both entries; FAR_FIELD gives pairEntryFarField (hybrid only); FACTORS gives pairEntry with
// rays = 0, the unoccluded factors. The arguments are pairEntry's. What one GPU thread does;
// a caller whose mode is a compile-time constant gets only that branch's code.
DAISY_HD PairFactors pairEntryInMode(int mode, uint i, uint j, DAISY_IN(PatchGeometry) gi,
                                     DAISY_IN(PatchGeometry) gj, int method, int level, int rays,
                                     uint seed, float clearanceRelative, BvhNodeBuffer nodes,
                                     BvhTriangleBuffer triangles) {
    PairFactors f;
    if (mode == DAISY_PAIR_MODE_VISIBILITY) {
        float v =
            pairEntryVisibility(i, j, gi, gj, rays, seed, clearanceRelative, nodes, triangles);
        f.fij = v;
        f.fji = v;
    } else if (mode == DAISY_PAIR_MODE_FAR_FIELD) {
        f = pairEntryFarField(gi, gj, level);
    } else {
        f = pairEntry(i, j, gi, gj, method, level, 0, seed, clearanceRelative, nodes, triangles);
    }
    return f;
}

DAISY_SHARED_END

#endif  // DAISY_SHARED_PAIR_KERNEL_H
