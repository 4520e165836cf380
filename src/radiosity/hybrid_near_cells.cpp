#include "radiosity/hybrid_near_cells.h"

#include "shared/config.h"
#include "shared/formfactor.h"

namespace daisy {
namespace {

using shared::ClippedPolygon;
using shared::PatchGeometry;
using shared::QuadratureCell;
using shared::vec3;

// Appends the three points of shared::threePointRule on the triangle (a, b, c), in its order.
void addThreePoints(vec3 a, vec3 b, vec3 c, const PatchGeometry& i, const PatchGeometry& j,
                    std::vector<FarFieldScratch::Point>& points) {
    const vec3 s = a + b + c;
    points.push_back({(s + a * 3.0f) * (1.0f / 6.0f), &i, &j});
    points.push_back({(s + b * 3.0f) * (1.0f / 6.0f), &i, &j});
    points.push_back({(s + c * 3.0f) * (1.0f / 6.0f), &i, &j});
}

// shared::threePointRule from its three values.
float threePointValue(const float* v) {
    float sum = v[0];
    sum += v[1];
    sum += v[2];
    return sum * (1.0f / 3.0f);
}

// Evaluates the scratch's near points into nearValues.
void evaluate(FarFieldScratch& s) {
    s.nearValues.resize(s.nearPoints.size());
    pointToTriangleFactors(s.nearPoints, s.nearValues.data());
}

}  // namespace

float hybridNearPairFactor(int level, const PatchGeometry& i, const PatchGeometry& j,
                           float relativeTolerance, FarFieldScratch& s) {
    // The shared kernel's names and expressions, step by step (shared/formfactor.h).
    using shared::cellCorners;
    using shared::distanceLowerBound;
    using shared::length;
    using shared::max;
    using shared::selectSubTriangle;
    const ClippedPolygon piece = shared::clipTriangleToHalfSpace(i.a, i.b, i.c, j.a, j.normal);
    if (piece.count < 3) return 0.0f;
    const vec3 jCentre = shared::patchCentroid(j);
    const float jRadius =
        max(max(length(j.a - jCentre), length(j.b - jCentre)), length(j.c - jCentre));
    float rootArea[2];
    uint32_t rootShared[2];
    const int cells = 1 << (2 * level);
    const float levelScale = 1.0f / float(1 << level);

    // The prologue: every cell of every root, its points in one batch.
    s.nearPoints.clear();
    s.nearCells.clear();
    for (int r = 0; r + 2 < piece.count; ++r) {
        const vec3 ra = piece.v[0];
        const vec3 rb = piece.v[r + 1];
        const vec3 rc = piece.v[r + 2];
        rootArea[r] = 0.5f * length(shared::cross(rb - ra, rc - ra));
        const float rootDiameter = max(max(length(rb - ra), length(rc - rb)), length(ra - rc));
        rootShared[r] = shared::sharedCornerMask(ra, rb, rc, j, rootDiameter);
        const vec3 rootCentre = (ra + rb + rc) * (1.0f / 3.0f);
        const bool coarse = distanceLowerBound(rootCentre, j, jCentre, jRadius) / rootDiameter >=
            DAISY_FF_MID_RATIO;
        const int rootLevel = coarse ? 0 : level;
        const int rootCells = coarse ? 1 : cells;
        const float cellScale = coarse ? 1.0f : levelScale;
        const float share = rootArea[r] * cellScale * cellScale / i.area;
        for (int t = 0; t < rootCells; ++t) {
            vec3 a = ra;
            vec3 b = rb;
            vec3 c = rc;
            cellCorners(uint32_t(t), rootLevel, a, b, c);
            const vec3 x = (a + b + c) * (1.0f / 3.0f);
            const float ratio =
                distanceLowerBound(x, j, jCentre, jRadius) / (rootDiameter * cellScale);
            const bool far = ratio >= DAISY_FF_FAR_RATIO;
            s.nearCells.push_back({share, uint32_t(t), uint8_t(r), far ? uint8_t(1) : uint8_t(3),
                                   !far && !(ratio >= DAISY_FF_MID_RATIO)});
            if (far) {
                s.nearPoints.push_back({x, &i, &j});
            } else {
                addThreePoints(a, b, c, i, j, s.nearPoints);
            }
        }
    }
    evaluate(s);
    float fixedPart = 0.0f;  // sum of share * mean over cells integrated by a fixed rule
    QuadratureCell list[DAISY_FF_MAX_CELLS];
    float listError[DAISY_FF_MAX_CELLS];
    float listPart[DAISY_FF_MAX_CELLS];  // share * cellMean of each listed cell
    int count = 0;
    std::size_t point = 0;
    for (const FarFieldScratch::PrologueCell& cell : s.nearCells) {
        float sum = 0.0f;
        for (int q = 0; q < cell.points; ++q)
            sum += s.nearValues[point++];
        if (cell.points == 1) {
            fixedPart += cell.share * sum;
        } else if (!cell.near) {
            fixedPart += cell.share * (sum * (1.0f / 3.0f));
        } else {
            const float value = sum * (1.0f / 3.0f);
            if (count < DAISY_FF_MAX_CELLS) {
                list[count].code = cell.code;
                list[count].depth = level;
                list[count].root = cell.root;
                list[count].value = value;
                count += 1;
            } else {
                fixedPart += cell.share * value;
            }
        }
    }

    // The refinement: the children of the listed cells in `pending` (all of them at first), in
    // one batch, then the shared kernel's decision; a split lists 4 cells whose children come
    // next.
    int pending[DAISY_FF_MAX_CELLS];
    int pendingCount = 0;
    for (int k = 0; k < count; ++k)
        pending[pendingCount++] = k;
    int keep = shared::min(count, (3 * DAISY_FF_MAX_CELLS) / 4);
    while (true) {
        s.nearPoints.clear();
        for (int p = 0; p < pendingCount; ++p) {
            const QuadratureCell& cell = list[pending[p]];
            vec3 ca = piece.v[0];
            vec3 cb = piece.v[cell.root + 1];
            vec3 cc = piece.v[cell.root + 2];
            cellCorners(cell.code, cell.depth, ca, cb, cc);
            for (uint32_t unit = 0; unit < 4; ++unit) {
                vec3 a = ca;
                vec3 b = cb;
                vec3 c = cc;
                selectSubTriangle(unit, a, b, c);
                addThreePoints(a, b, c, i, j, s.nearPoints);
            }
        }
        evaluate(s);
        for (int p = 0; p < pendingCount; ++p) {
            QuadratureCell& cell = list[pending[p]];
            const float* v = s.nearValues.data() + 12 * p;
            cell.child0 = threePointValue(v);
            cell.child1 = threePointValue(v + 3);
            cell.child2 = threePointValue(v + 6);
            cell.child3 = threePointValue(v + 9);
            const int r = cell.root;
            const float share = rootArea[r] / i.area / float(1 << (2 * cell.depth));
            listError[pending[p]] = shared::cellError(cell, share, rootShared[r]);
            listPart[pending[p]] = share * shared::cellMean(cell);
        }
        // Near cells past 3/4 of the list keep their children's mean (only for L >= 3).
        for (int k = keep; k < count; ++k)
            fixedPart += listPart[k];
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
        const QuadratureCell parent = list[worst];
        const float parentChild[4] = {parent.child0, parent.child1, parent.child2, parent.child3};
        for (int d = 0; d < 4; ++d) {
            const int slot = d == 0 ? worst : count + d - 1;
            list[slot].code = parent.code | (uint32_t(d) << uint32_t(2 * parent.depth));
            list[slot].depth = parent.depth + 1;
            list[slot].root = parent.root;
            list[slot].value = parentChild[d];
            pending[d] = slot;
        }
        pendingCount = 4;
        count += 3;
        keep = count;
    }
}

}  // namespace daisy
