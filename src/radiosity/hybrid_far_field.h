#pragma once
// The cpu backend's unoccluded pair factors: shared::pairFactors (shared/formfactor.h)
// with the hybrid method's commonest cases evaluated 4-16 points at a time across pairs. When no
// quadrature cell of i's clipped piece is near j (each is far, ratio >= DAISY_FF_FAR_RATIO: its
// centroid, or in the middle band from DAISY_FF_MID_RATIO: the three-point rule; a root that far
// is one cell; at the default L = 1 most pairs of a room), the pair's points join a batch whose
// point-to-triangle factors are evaluated in SIMD lanes, each lane with its own pair, by the same
// operations in the same order as the shared kernel, so every result is bit-identical to it
// (checked by tests/radiosity/hybrid_far_field_test.cpp); a point that sees j cut by its own
// plane gets the shared clip in its lane, and the contour sum over the polygon of 3 or 4 corners
// left. Pairs with a near cell and levels above 2 are the hybrid rule of hybrid_near_cells.h, its
// points also in lanes; the other methods are the shared kernel itself.
#include <cstdint>
#include <span>
#include <vector>

#include "shared/config.h"
#include "shared/gpu_types.h"

namespace daisy {

// Working memory of candidateFactorsCpu, reused between calls (one per thread).
struct FarFieldScratch {
    struct Point {
        shared::vec3 position;  // scene units
        const shared::PatchGeometry* receiver;  // i: the point's patch (its normal)
        const shared::PatchGeometry* target;  // j: the triangle the factor is to
    };
    struct Cell {
        float share;  // the cell's area over A_i
        uint32_t points;  // 1 (far: the centroid) or 3 (middle: threePointRule)
    };
    struct Pair {
        uint32_t cellEnd;  // one past the pair's last cell, or ~0 when not planned
        float direct;  // the shared kernel's factor, when not planned
    };
    std::vector<Point> points;
    std::vector<float> values;  // per point: the point-to-triangle factor
    std::vector<Cell> cells;
    std::vector<Pair> pairs;
    // hybridNearPairFactor's (hybrid_near_cells.h): the points of one batch and their values,
    // and the cells of the rule's prologue.
    struct PrologueCell {
        float share;  // the cell's area over A_i
        uint32_t code;  // its path from the root (shared::cellCorners)
        uint8_t root;  // which triangle of i's clipped piece
        uint8_t points;  // 1 (far), 3 (middle or near)
        bool near;  // listed for refinement
    };
    std::vector<Point> nearPoints;
    std::vector<float> nearValues;
    std::vector<PrologueCell> nearCells;
};

// What the far-field planner needs of a whole patch, computed once by the shared kernel's own
// expressions on its corners, so a pair whose clipped piece is the whole patch (most pairs)
// reads them instead of computing them again, bit-identical: the centroid (patchCentroid), the
// longest distance from it to a corner (hybridPairFactorWithin's jRadius), and the whole triangle
// as a root (its rootArea and rootDiameter). Not PatchGeometry::area, which may be the mesh's.
struct FarFieldPatch {
    shared::vec3 centroid;
    float radius;
    float rootArea;
    float rootDiameter;
};

// farFieldPatches(g)[p] for every patch g[p].
std::vector<FarFieldPatch> farFieldPatches(std::span<const shared::PatchGeometry> geometry);

// out[k] = shared::pointToTriangleFactor(p.position, p.receiver->normal, *p.target) for every
// point p = points[k], bit-identical, in SSE, AVX2 or AVX-512 lanes as cpuIsa() allows
// (core/cpu_isa.h; the final gather's lights use it too). s.values is not touched.
void pointToTriangleFactors(std::span<const FarFieldScratch::Point> points, float* out);

// shared::pairFactors(method, level, i, j), with the hybrid method's far cells vectorised.
shared::PairFactors pairFactorsCpu(int method, int level, const shared::PatchGeometry& i,
                                   const shared::PatchGeometry& j);

// pairFactorsCpu of a pair known not to face away (the driver's candidates, pair_evaluator.h):
// the same values without testing shared::facingAway again.
shared::PairFactors candidatePairFactorsCpu(int method, int level, const shared::PatchGeometry& i,
                                            const shared::PatchGeometry& j);

// out[k] = candidatePairFactorsCpu(method, level, geometry[pairs[k].i], geometry[pairs[k].j])
// with both entries clamped to >= 0, for every k, the far cells of all the pairs evaluated
// together. patches = farFieldPatches(geometry); out.size() >= pairs.size(). The hybrid rule's
// near cells refine to `relativeTolerance` of the factor (shared::hybridPairFactorWithin).
void candidateFactorsCpu(int method, int level, std::span<const shared::PatchGeometry> geometry,
                         std::span<const FarFieldPatch> patches,
                         std::span<const shared::PairIndex> pairs,
                         std::span<shared::PairFactors> out, FarFieldScratch& scratch,
                         float relativeTolerance = DAISY_FF_REL_TOL);

}  // namespace daisy
