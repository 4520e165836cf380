// Unoccluded form factors between triangular patches (DESIGN.md section 3): the exact
// differential-area-to-polygon factor and the per-pair kernels of the riemann, nusselt and hybrid
// methods. Visibility is not here: the driver multiplies by V_ij from shadow rays.
// Patches are one-sided: only the half-space in front of a patch (along its normal) emits or
// receives. All lengths in scene units; factors dimensionless.
#ifndef DAISY_SHARED_FORMFACTOR_H
#define DAISY_SHARED_FORMFACTOR_H

#include "config.h"
#include "gpu_types.h"
#include "prelude.h"
#include "sampling.h"

DAISY_SHARED_BEGIN

// A triangle clipped by a plane: at most 4 corners.
struct ClippedPolygon {
    vec3 v[4];
    int count;
};

// Tolerance on "in front of a plane", relative to the distances involved: float rounding of
// coplanar corners is ~1e-7 of the coordinates; anything within 1e-5 counts as on the plane.
DAISY_HD float planeEpsilon(float scale) {
    return 1.0e-5f * scale;
}

// Bound on the float rounding of coordinates near x and y (2^-22 of their largest components,
// four half-ulps): the part of "on the plane" that does not shrink with the distances, which
// matters for patches far from the origin relative to their size.
DAISY_HD float coordinateEpsilon(vec3 x, vec3 y) {
    float mx = max(abs(x.x), abs(y.x));
    float my = max(abs(x.y), abs(y.y));
    float mz = max(abs(x.z), abs(y.z));
    return 2.4e-7f * max(max(mx, my), mz);
}

// True when j has no point strictly in front of i's plane or i none in front of j's, so F_ij =
// F_ji = 0 with no rays: back-to-back, facing away and coplanar pairs. "Strictly" allows float
// rounding: planeEpsilon of each corner's distance from the plane's anchor plus the rounding of
// the coordinates themselves (coordinateEpsilon), so coplanar patches far from the origin stay
// exactly 0.
DAISY_HD bool facingAway(DAISY_IN(PatchGeometry) i, DAISY_IN(PatchGeometry) j) {
    vec3 cj[3] = {j.a, j.b, j.c};
    vec3 ci[3] = {i.a, i.b, i.c};
    bool jInFrontOfI = false;
    bool iInFrontOfJ = false;
    for (int k = 0; k < 3; ++k) {
        vec3 dj = cj[k] - i.a;
        float ej = planeEpsilon(length(dj)) + coordinateEpsilon(cj[k], i.a);
        if (dot(i.normal, dj) > ej) jInFrontOfI = true;
        vec3 di = ci[k] - j.a;
        float ei = planeEpsilon(length(di)) + coordinateEpsilon(ci[k], j.a);
        if (dot(j.normal, di) > ei) iInFrontOfJ = true;
    }
    return !(jInFrontOfI && iInFrontOfJ);
}

// Clips the triangle (a, b, c) to the closed half-space dot(n, x - p) >= 0 (Sutherland &
// Hodgman 1974, one plane). Corners within planeEpsilon of the plane count as on it, so an edge
// lying in the plane (a shared edge) is kept whole. Orientation is preserved. The tolerance is
// compared squared (s^2 <= planeEpsilon(1)^2 |d|^2): no square root a corner.
DAISY_HD ClippedPolygon clipTriangleToHalfSpace(vec3 a, vec3 b, vec3 c, vec3 p, vec3 n) {
    vec3 in3[3] = {a, b, c};
    float s[3];
    float eps2 = planeEpsilon(1.0f) * planeEpsilon(1.0f);
    for (int k = 0; k < 3; ++k) {
        vec3 d = in3[k] - p;
        s[k] = dot(n, d);
        if (s[k] * s[k] <= eps2 * dot(d, d)) s[k] = 0.0f;
    }
    ClippedPolygon clipped;
    if (s[0] >= 0.0f && s[1] >= 0.0f && s[2] >= 0.0f) {  // wholly in front: the loop's result
        clipped.v[0] = a;
        clipped.v[1] = b;
        clipped.v[2] = c;
        clipped.count = 3;
        return clipped;
    }
    clipped.count = 0;
    for (int k = 0; k < 3; ++k) {
        int k1 = k == 2 ? 0 : k + 1;
        if (s[k] >= 0.0f) {
            clipped.v[clipped.count] = in3[k];
            clipped.count += 1;
        }
        if ((s[k] > 0.0f && s[k1] < 0.0f) || (s[k] < 0.0f && s[k1] > 0.0f)) {
            float t = s[k] / (s[k] - s[k1]);
            clipped.v[clipped.count] = mix(in3[k], in3[k1], t);
            clipped.count += 1;
        }
    }
    return clipped;
}

// Exact factor from a differential area at p with unit normal n to the polygon `poly`, which
// must lie in p's closed front half-space and be seen from its front (counter-clockwise about
// its normal, as viewed from p): Lambert's contour formula, as used by Baum, Rushmeier & Winget
// 1989 (SIGGRAPH, "Improving Radiosity Solutions Through the Use of Analytically Determined
// Form-Factors"):
//   F = -1/(2 pi) sum_k gamma_k dot(n, unit(v_k x v_k+1)),  v_k = corner_k - p,
// gamma_k the angle between v_k and v_k+1, taken as atan2(|v_k x e_k|, v_k . v_k+1) with the edge
// e_k = corner_k+1 - corner_k (v_k x v_k+1 = v_k x e_k without the cancellation).
DAISY_HD float pointToPolygonFactor(vec3 p, vec3 n, DAISY_IN(ClippedPolygon) poly) {
    float sum = 0.0f;
    vec3 v[4];
    for (int k = 0; k < poly.count; ++k) {
        v[k] = poly.v[k] - p;
    }
    for (int k = 0; k < poly.count; ++k) {
        int k1 = k + 1 == poly.count ? 0 : k + 1;
        vec3 g = cross(v[k], poly.v[k1] - poly.v[k]);
        float gLength = length(g);
        if (gLength > 0.0f) {
            float gamma = atan(gLength, dot(v[k], v[k1]));
            sum += gamma * (dot(n, g) / gLength);
        }
    }
    return max(0.0f, -sum * DAISY_INV_TWO_PI);
}

// Unoccluded factor from a differential area at p with unit normal n to triangle t: 0 when p is
// not in front of t (one-sided receiver); otherwise t is clipped to p's front half-space first,
// so a t straddling p's tangent plane counts only the part p can see. "In front" has no
// tolerance: the factor is continuous as p approaches t's plane outside t (it tends to 0), and
// over t it tends to 1, which a tolerance relative to |p - t.a| would cut off for points within
// 1e-5 of a long patch's length from it (nearly coincident patches, slivers' neighbours).
DAISY_HD float pointToTriangleFactor(vec3 p, vec3 n, DAISY_IN(PatchGeometry) t) {
    vec3 d = p - t.a;
    if (dot(t.normal, d) <= 0.0f) return 0.0f;
    ClippedPolygon poly = clipTriangleToHalfSpace(t.a, t.b, t.c, p, n);
    if (poly.count < 3) return 0.0f;
    return pointToPolygonFactor(p, n, poly);
}

// Corners of quadrature cell `code` at `depth` levels below the root triangle (a, b, c): the
// base-4 digits of code, least significant first, pick the selectSubTriangle child per level.
DAISY_HD void cellCorners(uint code, int depth, DAISY_INOUT(vec3) a, DAISY_INOUT(vec3) b,
                          DAISY_INOUT(vec3) c) {
    for (int l = 0; l < depth; ++l) {
        selectSubTriangle((code >> uint(2 * l)) & 3u, a, b, c);
    }
}

// Kernel of the riemann rule between points xi on i and xj on j: cos_i cos_j / (pi r^2), 0
// unless each point is in front of the other's patch.
DAISY_HD float riemannKernel(vec3 xi, vec3 ni, vec3 xj, vec3 nj) {
    vec3 d = xj - xi;
    float r2 = dot(d, d);
    float cosI = dot(ni, d);
    float cosJ = -dot(nj, d);
    if (cosI <= 0.0f || cosJ <= 0.0f || r2 <= 0.0f) return 0.0f;
    return cosI * cosJ / (r2 * r2) * DAISY_INV_PI;
}

// riemann: the kernel at all pairs of 4^L cell centroids, one set on each patch, times the cell
// area of j, averaged over i's cells (the seed's double-area rule; L = 1 is the 4x4 rule).
// Over-estimates near shared edges and corners. The level-L midpoint cells of a triangle are the
// n x n triangular grid (n = 2^L): upward cells with centroid barycentrics ((r + 1/3) / n,
// (s + 1/3) / n) on (b, c), r + s <= n - 1, and downward ones at (r + 2/3, s + 2/3) / n,
// r + s <= n - 2; j's are enumerated so, without decoding cell paths in the inner loop.
DAISY_HD float riemannPairFactor(int level, DAISY_IN(PatchGeometry) i, DAISY_IN(PatchGeometry) j) {
    int cells = 1 << (2 * level);
    int n = 1 << level;
    float inv = 1.0f / float(n);
    vec3 eb = j.b - j.a;
    vec3 ec = j.c - j.a;
    float sum = 0.0f;
    for (int p = 0; p < cells; ++p) {
        vec3 ia = i.a;
        vec3 ib = i.b;
        vec3 ic = i.c;
        cellCorners(uint(p), level, ia, ib, ic);
        vec3 xi = (ia + ib + ic) * (1.0f / 3.0f);
        for (int r = 0; r < n; ++r) {
            for (int s = 0; s < n - r; ++s) {
                float u = (float(r) + 1.0f / 3.0f) * inv;
                float v = (float(s) + 1.0f / 3.0f) * inv;
                sum += riemannKernel(xi, i.normal, j.a + eb * u + ec * v, j.normal);
                if (r + s < n - 1) {
                    u = (float(r) + 2.0f / 3.0f) * inv;
                    v = (float(s) + 2.0f / 3.0f) * inv;
                    sum += riemannKernel(xi, i.normal, j.a + eb * u + ec * v, j.normal);
                }
            }
        }
    }
    return sum * (j.area / float(cells)) / float(cells);
}

// nusselt: the exact point-to-polygon factor from i's centroid to j.
DAISY_HD float nusseltPairFactor(DAISY_IN(PatchGeometry) i, DAISY_IN(PatchGeometry) j) {
    return pointToTriangleFactor(patchCentroid(i), i.normal, j);
}

// Lower bound on the distance from a point x to patch j, in scene units: the larger of the
// distances to j's plane and to j's bounding sphere (centre jCentre, radius jRadius).
DAISY_HD float distanceLowerBound(vec3 x, DAISY_IN(PatchGeometry) j, vec3 jCentre, float jRadius) {
    return max(abs(dot(j.normal, x - j.a)), length(x - jCentre) - jRadius);
}

// Mean over the triangle (a, b, c) of f(x) = pointToTriangleFactor(x, n, j) by the degree-2
// three-point rule at barycentrics (2/3, 1/6, 1/6) and permutations (Strang & Fix 1973), which are
// the centroids of the three corner children of the midpoint subdivision. It equals Richardson
// extrapolation of the centroid rule, and never evaluates f on the cell's boundary.
DAISY_HD float threePointRule(vec3 a, vec3 b, vec3 c, vec3 n, DAISY_IN(PatchGeometry) j) {
    vec3 s = a + b + c;
    float sum = pointToTriangleFactor((s + a * 3.0f) * (1.0f / 6.0f), n, j);
    sum += pointToTriangleFactor((s + b * 3.0f) * (1.0f / 6.0f), n, j);
    sum += pointToTriangleFactor((s + c * 3.0f) * (1.0f / 6.0f), n, j);
    return sum * (1.0f / 3.0f);
}

// Bit k (k = 0, 1, 2 for a, b, c) set when that corner of the triangle (a, b, c) coincides with
// a corner of j (within planeEpsilon of `size`): the patches share a vertex there.
DAISY_HD uint sharedCornerMask(vec3 a, vec3 b, vec3 c, DAISY_IN(PatchGeometry) j, float size) {
    vec3 corners[3] = {a, b, c};
    float eps = planeEpsilon(size);
    uint mask = 0u;
    for (int k = 0; k < 3; ++k) {
        vec3 x = corners[k];
        if (distance(x, j.a) <= eps || distance(x, j.b) <= eps || distance(x, j.c) <= eps) {
            mask |= 1u << uint(k);
        }
    }
    return mask;
}

// True when cell (code, depth) of a root triangle contains root corner k, for a k in `mask`:
// all its digits are k (selectSubTriangle's child k keeps corner k).
DAISY_HD bool cellHasCorner(uint code, int depth, uint mask) {
    uint digits = (1u << uint(2 * depth)) - 1u;
    for (uint k = 0u; k < 3u; ++k) {
        if ((mask & (1u << k)) != 0u && code == ((k * 0x55555555u) & digits)) return true;
    }
    return false;
}

// One cell of the hybrid refinement list: where it is, threePointRule on the cell itself and on
// each of its 4 children (their mean is the cell's estimate of the mean of f). 32 bytes.
struct QuadratureCell {
    uint code;  // path from its root triangle, 2 bits a level (cellCorners)
    int depth;  // levels below the root triangle
    int root;  // which triangle of the clipped piece (0 or 1)
    float value;  // threePointRule on the cell, mean of f (dimensionless)
    float child0;  // threePointRule on child 0..3, mean of f (dimensionless)
    float child1;
    float child2;
    float child3;
};

DAISY_HD float cellMean(DAISY_IN(QuadratureCell) cell) {
    return 0.25f * (cell.child0 + cell.child1 + cell.child2 + cell.child3);
}

// The error estimate of an evaluated cell as a fraction of A_i, given share = A_cell / A_i:
// share * |children's mean - value|, the classic comparison of a rule on a cell and on its
// children. At a vertex shared with j (a root corner in sharedCorners), f depends on the
// direction only, so that difference can vanish by accident at every scale: there the estimate
// is at least share * (largest child deviation) / 16.
DAISY_HD float cellError(DAISY_IN(QuadratureCell) cell, float share, uint sharedCorners) {
    float error = share * abs(cellMean(cell) - cell.value);
    if (sharedCorners != 0u && cellHasCorner(cell.code, cell.depth, sharedCorners)) {
        float deviation = max(max(abs(cell.child0 - cell.value), abs(cell.child1 - cell.value)),
                              max(abs(cell.child2 - cell.value), abs(cell.child3 - cell.value)));
        error = max(error, share * deviation * (1.0f / 16.0f));
    }
    return error;
}

// hybrid (Baum, Rushmeier & Winget 1989): F_ij = (1/A_i) integral over i of f(x), the
// exact pointToTriangleFactor from x on i to j. i is first clipped to j's front half-space (the
// rest sees j's back: f = 0), and each clipped piece (root) split into 4^L cells, unless the
// root is already DAISY_FF_MID_RATIO of its own diameter from j: then it is one cell (the rules
// below are as accurate on it as on its children, at a quarter of the points). By a cell's distance
// to j in cell diameters (distanceLowerBound): from DAISY_FF_FAR_RATIO on, its centroid value;
// from DAISY_FF_MID_RATIO on, threePointRule; nearer, the cell joins a globally adaptive scheme
// (as in QUADPACK's qag, Piessens et al. 1983): each listed cell carries the mean of its children's
// threePointRule and an error estimate (cellError); while the summed estimate exceeds
// relativeTolerance (DAISY_FF_REL_TOL in hybridPairFactorWith) times the current F_ij plus
// DAISY_FF_ABS_TOL, the cell with the largest estimate is split into its children. f stays finite
// at a shared edge (its gradient has a log singularity) and depends only on the direction at a
// shared vertex, so the refinement converges there too. The list holds DAISY_FF_MAX_CELLS cells;
// when full (or a cell reaches DAISY_FF_MAX_DEPTH) refinement stops. Near cells beyond 3/4 of the
// list (only for L >= 3) keep their children's mean unrefined, and beyond the whole list (only for
// L >= 4) their own threePointRule. Listed cells are evaluated one child (one threePointRule) at a
// time in a single loop: a SIMD device that runs every branch (lavapipe) or waits for its slowest
// lane (any GPU) then pays for the children a pair really needs, not for every call site of the
// rule. Preconditions: i.area > 0, j.area > 0. `nearCells` false compiles the refinement out (a
// constant at every call site): a pair with a near cell then returns DAISY_FF_NEEDS_NEAR_CELLS as
// soon as it meets one, and any other pair the value it has with nearCells true (nothing listed:
// the refinement changes nothing). A device that runs every branch of a shader, masked (lavapipe),
// then evaluates a far pair without paying for the refinement's code (docs/backends.md, "The
// far-field pass").
DAISY_HD float hybridPairFactorWithin(int level, DAISY_IN(PatchGeometry) i,
                                      DAISY_IN(PatchGeometry) j, bool nearCells,
                                      float relativeTolerance) {
    ClippedPolygon piece = clipTriangleToHalfSpace(i.a, i.b, i.c, j.a, j.normal);
    if (piece.count < 3) return 0.0f;
    vec3 jCentre = patchCentroid(j);
    float jRadius = max(max(length(j.a - jCentre), length(j.b - jCentre)), length(j.c - jCentre));
    float fixedPart = 0.0f;  // sum of share * mean over cells integrated by a fixed rule
    QuadratureCell list[DAISY_FF_MAX_CELLS];
    float listError[DAISY_FF_MAX_CELLS];
    float listPart[DAISY_FF_MAX_CELLS];  // share * cellMean of each listed cell
    int count = 0;
    float rootArea[2];
    uint rootShared[2];
    int cells = 1 << (2 * level);
    float levelScale = 1.0f / float(1 << level);
    for (int r = 0; r + 2 < piece.count; ++r) {
        vec3 ra = piece.v[0];
        vec3 rb = piece.v[r + 1];
        vec3 rc = piece.v[r + 2];
        rootArea[r] = 0.5f * length(cross(rb - ra, rc - ra));
        float rootDiameter = max(max(length(rb - ra), length(rc - rb)), length(ra - rc));
        rootShared[r] = sharedCornerMask(ra, rb, rc, j, rootDiameter);
        // A root at least DAISY_FF_MID_RATIO of its own diameter from j is one cell: the far or
        // middle rule on the whole root is within the error bands the cells would have.
        vec3 rootCentre = (ra + rb + rc) * (1.0f / 3.0f);
        bool coarse = distanceLowerBound(rootCentre, j, jCentre, jRadius) / rootDiameter >=
            DAISY_FF_MID_RATIO;
        int rootLevel = coarse ? 0 : level;
        int rootCells = coarse ? 1 : cells;
        float cellScale = coarse ? 1.0f : levelScale;
        float share = rootArea[r] * cellScale * cellScale / i.area;
        for (int t = 0; t < rootCells; ++t) {
            vec3 a = ra;
            vec3 b = rb;
            vec3 c = rc;
            cellCorners(uint(t), rootLevel, a, b, c);
            vec3 x = (a + b + c) * (1.0f / 3.0f);
            float ratio = distanceLowerBound(x, j, jCentre, jRadius) / (rootDiameter * cellScale);
            // The centroid rule (far) or threePointRule, summed in one loop: one call site, so
            // a SIMD device evaluates 1 point a cell where all its lanes are far, not 4.
            int points = ratio >= DAISY_FF_FAR_RATIO ? 1 : 3;
            vec3 s = a + b + c;
            float sum = 0.0f;
            for (int q = 0; q < points; ++q) {
                vec3 corner = q == 0 ? a : (q == 1 ? b : c);
                vec3 p = points == 1 ? x : (s + corner * 3.0f) * (1.0f / 6.0f);
                sum += pointToTriangleFactor(p, i.normal, j);
            }
            if (ratio >= DAISY_FF_FAR_RATIO) {
                fixedPart += share * sum;
            } else if (ratio >= DAISY_FF_MID_RATIO) {
                fixedPart += share * (sum * (1.0f / 3.0f));
            } else {
                if (!nearCells) return DAISY_FF_NEEDS_NEAR_CELLS;
                float value = sum * (1.0f / 3.0f);
                if (count < DAISY_FF_MAX_CELLS) {
                    list[count].code = uint(t);
                    list[count].depth = level;
                    list[count].root = r;
                    list[count].value = value;
                    count += 1;
                } else {
                    fixedPart += share * value;
                }
            }
        }
    }
    if (!nearCells) return fixedPart;
    // Listed cells whose children are still to be evaluated: `current` (child `unit` next),
    // then slot `pendingFirst` when >= 0, then the slots [pendingNext, pendingEnd).
    int pendingFirst = -1;
    int pendingNext = 0;
    int pendingEnd = count;
    int current = -1;
    int unit = 0;
    vec3 ca = vec3(0.0f);
    vec3 cb = vec3(0.0f);
    vec3 cc = vec3(0.0f);
    float childValue[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    int keep = min(count, (3 * DAISY_FF_MAX_CELLS) / 4);
    while (true) {
        while (true) {
            if (current < 0) {
                if (pendingFirst >= 0) {
                    current = pendingFirst;
                    pendingFirst = -1;
                } else if (pendingNext < pendingEnd) {
                    current = pendingNext;
                    pendingNext += 1;
                } else {
                    break;
                }
                unit = 0;
                int r = list[current].root;
                ca = piece.v[0];
                cb = piece.v[r + 1];
                cc = piece.v[r + 2];
                cellCorners(list[current].code, list[current].depth, ca, cb, cc);
            }
            vec3 a = ca;
            vec3 b = cb;
            vec3 c = cc;
            selectSubTriangle(uint(unit), a, b, c);
            childValue[unit] = threePointRule(a, b, c, i.normal, j);
            unit += 1;
            if (unit == 4) {
                list[current].child0 = childValue[0];
                list[current].child1 = childValue[1];
                list[current].child2 = childValue[2];
                list[current].child3 = childValue[3];
                int r = list[current].root;
                float share = rootArea[r] / i.area / float(1 << (2 * list[current].depth));
                listError[current] = cellError(list[current], share, rootShared[r]);
                listPart[current] = share * cellMean(list[current]);
                current = -1;
            }
        }
        // Near cells past 3/4 of the list keep their children's mean (only for L >= 3).
        for (int k = keep; k < count; ++k) {
            fixedPart += listPart[k];
        }
        count = keep;
        float total = fixedPart;
        float errorSum = 0.0f;
        int worst = -1;
        float worstError = 0.0f;
        for (int k = 0; k < count; ++k) {
            total += listPart[k];
            errorSum += listError[k];
            if (listError[k] > worstError && list[k].depth + 1 < DAISY_FF_MAX_DEPTH) {
                worst = k;
                worstError = listError[k];
            }
        }
        if (errorSum <= relativeTolerance * total + DAISY_FF_ABS_TOL || worst < 0 ||
            count + 3 > DAISY_FF_MAX_CELLS) {
            return total;
        }
        QuadratureCell parent = list[worst];
        float parentChild[4] = {parent.child0, parent.child1, parent.child2, parent.child3};
        for (int d = 0; d < 4; ++d) {
            int slot = d == 0 ? worst : count + d - 1;
            list[slot].code = parent.code | (uint(d) << uint(2 * parent.depth));
            list[slot].depth = parent.depth + 1;
            list[slot].root = parent.root;
            list[slot].value = parentChild[d];
        }
        pendingFirst = worst;
        pendingNext = count;
        pendingEnd = count + 3;
        count += 3;
        keep = count;
    }
    return 0.0f;
}

// The hybrid rule at the accuracy of F (DAISY_FF_REL_TOL).
DAISY_HD float hybridPairFactorWith(int level, DAISY_IN(PatchGeometry) i, DAISY_IN(PatchGeometry) j,
                                    bool nearCells) {
    return hybridPairFactorWithin(level, i, j, nearCells, DAISY_FF_REL_TOL);
}

// Unoccluded F_ij (fraction of the energy leaving i that arrives at j) by `method`
// (DAISY_METHOD_*), with quadrature level `level` (clamped to 0..DAISY_MAX_QUADRATURE_LEVEL).
// The caller chooses the direction: i gets the quadrature points (the accurate choice is the
// smaller patch; pairFactors makes it). The stochastic method has no unoccluded kernel (its rays
// carry visibility): it returns 0, as do unknown methods and facingAway pairs. `nearCells` is
// hybridPairFactorWith's (pairFactorUnoccluded: true).
DAISY_HD float pairFactorUnoccludedWith(int method, int level, DAISY_IN(PatchGeometry) i,
                                        DAISY_IN(PatchGeometry) j, bool nearCells) {
    if (facingAway(i, j)) return 0.0f;
    int l = clamp(level, 0, DAISY_MAX_QUADRATURE_LEVEL);
    if (method == DAISY_METHOD_RIEMANN) return riemannPairFactor(l, i, j);
    if (method == DAISY_METHOD_NUSSELT) return nusseltPairFactor(i, j);
    if (method == DAISY_METHOD_HYBRID) return hybridPairFactorWith(l, i, j, nearCells);
    return 0.0f;
}

DAISY_HD float pairFactorUnoccluded(int method, int level, DAISY_IN(PatchGeometry) i,
                                    DAISY_IN(PatchGeometry) j) {
    return pairFactorUnoccludedWith(method, level, i, j, true);
}

// Both unoccluded factors of the unordered pair {i, j}: computed once in the accurate direction
// (quadrature on the patchPrecedes-first patch, the smaller one) and the other entry from
// reciprocity A_i F_ij = A_j F_ji (DESIGN.md section 3). Swapping i and j swaps the results.
// The kernel has one call site: a compiler would otherwise inline the hybrid rule twice, with a
// refinement list each (twice the per-thread stack under nvcc), and a SIMD device that runs
// both sides of a branch (lavapipe) would evaluate it twice per pair. `nearCells` is
// hybridPairFactorWith's: false gives both entries DAISY_FF_NEEDS_NEAR_CELLS for a hybrid pair
// with a near cell (pairFactors: true).
DAISY_HD PairFactors pairFactorsWith(int method, int level, DAISY_IN(PatchGeometry) i,
                                     DAISY_IN(PatchGeometry) j, bool nearCells) {
    bool swapped = patchPrecedes(j, i);
    PatchGeometry first = swapped ? j : i;
    PatchGeometry second = swapped ? i : j;
    float f = pairFactorUnoccludedWith(method, level, first, second, nearCells);
    PairFactors factors;
    if (!nearCells && f == DAISY_FF_NEEDS_NEAR_CELLS) {
        factors.fij = f;
        factors.fji = f;
    } else if (swapped) {
        factors.fji = f;
        factors.fij = f * (j.area / i.area);
    } else {
        factors.fij = f;
        factors.fji = f * (i.area / j.area);
    }
    return factors;
}

DAISY_HD PairFactors pairFactors(int method, int level, DAISY_IN(PatchGeometry) i,
                                 DAISY_IN(PatchGeometry) j) {
    return pairFactorsWith(method, level, i, j, true);
}

DAISY_SHARED_END

#endif  // DAISY_SHARED_FORMFACTOR_H
