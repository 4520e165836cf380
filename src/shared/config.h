// Constants that C++, CUDA and GLSL all need (STYLE.md rule 4), #defined once, each with its
// reason. Plain literals only: this file is read by the GLSL preprocessor too.
#ifndef DAISY_SHARED_CONFIG_H
#define DAISY_SHARED_CONFIG_H

// pi and 1/pi in float: GLSL has no M_PI.
#define DAISY_PI 3.14159265358979f
#define DAISY_INV_PI 0.318309886183791f
#define DAISY_INV_TWO_PI 0.159154943091895f

// Form-factor methods (DESIGN.md section 3); the numbers are what the CLI's --method maps to and
// what a GPU kernel receives as a push constant.
#define DAISY_METHOD_RIEMANN 0
#define DAISY_METHOD_NUSSELT 1
#define DAISY_METHOD_STOCHASTIC 2
#define DAISY_METHOD_HYBRID 3

// Default --quadrature level L: 4^L quadrature cells per patch (L = 1 is the 4x4 Riemann rule).
#define DAISY_DEFAULT_QUADRATURE_LEVEL 1
// Largest accepted L: 4^6 = 4096 points a side is already far past any accuracy need.
#define DAISY_MAX_QUADRATURE_LEVEL 6

// Hybrid quadrature (formfactor.h), by a cell's distance to the other patch in cell diameters:
// from FAR_RATIO on the centroid rule (measured error below ~0.1 / ratio^2 of A_j / (pi r^2)),
// from MID_RATIO on the 3-point rule (below ~1e-3 / ratio^2 of it), nearer the adaptive rule.
#define DAISY_FF_FAR_RATIO 16.0f
#define DAISY_FF_MID_RATIO 4.0f
// Hybrid refinement stops when the summed error estimate of the adaptive cells is below this
// fraction of F_ij (measured errors of near pairs stay below ~4e-4; see formfactor_test.cpp).
#define DAISY_FF_REL_TOL 3.0e-4f
// ... or below this absolute amount (a fraction of A_i, like F_ij): the float resolution of the
// point factors the estimate compares (about 1e-7 for values near 1). A pair whose F_ij is
// itself at that level (patches coplanar only to an exporter's rounding) otherwise refines to
// the cell cap without ever meeting the relative rule: 313 point factors a close pair instead of
// 21 on the double-sided Blender-style Cornell box.
#define DAISY_FF_ABS_TOL 1.0e-7f
// Deepest cell, in levels below the patch: 4^-12 of its area, where float positions run out.
#define DAISY_FF_MAX_DEPTH 12
// Capacity of the hybrid's explicit cell list (no recursion in the dialect): 128 cells of 28 bytes
// in registers/local memory; allows ~40 splits, far more than a shared edge or vertex needs.
#define DAISY_FF_MAX_CELLS 128

// Entries of the BVH traversal stack (bvh_traverse.h), one per tree level below the root: the
// builder (raycast/flat_bvh.cpp) caps the depth at this, so the stack cannot overflow. 64 uints
// are 256 bytes of local memory per GPU thread.
#define DAISY_BVH_STACK_SIZE 64
// Shadow segments are tested for t in (MARGIN, 1 - MARGIN) of their length: the relative end
// margin of the ray caster's segments (RayCaster::kSegmentMargin), so both test the same span.
#define DAISY_SEGMENT_MARGIN 1.0e-5f

// What one specialisation of the pair kernel (shaders/form_factors.comp.glsl) computes per pair:
// the unoccluded factors alone, or V_ij alone (in both fields), so that the vulkan backend runs
// the quadrature only for pairs some ray reaches (lavapipe runs every branch of a shader); or
// the hybrid method's unoccluded factors without the adaptive refinement's code
// (pairEntryFarField, shared/pair_kernel.h), DAISY_FF_NEEDS_NEAR_CELLS for the pairs that need it.
#define DAISY_PAIR_MODE_FACTORS 0
#define DAISY_PAIR_MODE_VISIBILITY 1
#define DAISY_PAIR_MODE_FAR_FIELD 2

// What hybridPairFactorWith(..., false) returns for a pair with a near cell (and
// pairEntryFarField in both entries): no factor is negative by more than rounding.
#define DAISY_FF_NEEDS_NEAR_CELLS (-1.0f)

// Invocations per workgroup of the pair kernel (shaders/form_factors.comp.glsl); the host
// dispatches ceil(pairCount / DAISY_PAIR_WORKGROUP_SIZE) groups.
#define DAISY_PAIR_WORKGROUP_SIZE 64

#endif  // DAISY_SHARED_CONFIG_H
