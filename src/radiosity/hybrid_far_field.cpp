#include "radiosity/hybrid_far_field.h"

#include "shared/config.h"
#include "shared/formfactor.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace daisy {
namespace {

constexpr uint32_t kNotPlanned = 0xffffffffu;

using shared::ClippedPolygon;
using shared::PairIndex;
using shared::PatchGeometry;
using shared::vec3;

// Cells per root triangle the planned path takes (L <= 2); finer levels are the shared kernel's.
constexpr int kMaxCellsPerRoot = 16;
#if defined(__SSE2__)

// Four floats, one per quadrature point. Every helper is the shared dialect's operation
// (shared/prelude.h) lane by lane, with the same operand order, so each lane rounds as the
// scalar code does (no FMA: baseline x86-64 has none, and nothing here asks for one).
using Lane = __m128;

Lane splat(float v) {
    return _mm_set1_ps(v);
}
Lane select(Lane mask, Lane a, Lane b) {
    return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b));
}
// dot(a, b) = a.x * b.x + a.y * b.y + a.z * b.z, summed left to right.
Lane dot3(Lane ax, Lane ay, Lane az, Lane bx, Lane by, Lane bz) {
    return _mm_add_ps(_mm_add_ps(_mm_mul_ps(ax, bx), _mm_mul_ps(ay, by)), _mm_mul_ps(az, bz));
}

// shared::daisyAtan2 (prelude.h), step by step.
Lane atan2Lanes(Lane y, Lane x) {
    const Lane signMask = splat(-0.0f);
    const Lane zero = _mm_setzero_ps();
    const Lane ax = _mm_andnot_ps(signMask, x);
    const Lane ay = _mm_andnot_ps(signMask, y);
    const Lane yOverX = _mm_cmpgt_ps(ay, ax);
    const Lane greater = select(yOverX, ay, ax);  // max(ax, ay) = ay > ax ? ay : ax
    const Lane lesser = select(_mm_cmplt_ps(ay, ax), ay, ax);  // min(ax, ay)
    const Lane upper = _mm_cmpgt_ps(lesser, _mm_mul_ps(splat(0.414213562f), greater));
    const Lane num = select(upper, _mm_sub_ps(lesser, greater), lesser);
    const Lane den = select(upper, _mm_add_ps(lesser, greater), greater);
    const Lane a = select(_mm_cmpgt_ps(den, zero), _mm_div_ps(num, den), zero);
    const Lane z = _mm_mul_ps(a, a);
    Lane p = _mm_sub_ps(_mm_mul_ps(splat(8.05374449538e-2f), z), splat(1.38776856032e-1f));
    p = _mm_add_ps(_mm_mul_ps(p, z), splat(1.99777106478e-1f));
    p = _mm_sub_ps(_mm_mul_ps(p, z), splat(3.33329491539e-1f));
    Lane r = _mm_add_ps(select(upper, splat(0.785398163f), zero),
                        _mm_add_ps(a, _mm_mul_ps(_mm_mul_ps(a, z), p)));
    r = select(yOverX, _mm_sub_ps(splat(1.57079633f), r), r);
    r = select(_mm_cmplt_ps(x, zero), _mm_sub_ps(splat(3.14159265f), r), r);
    return select(_mm_cmplt_ps(y, zero), _mm_xor_ps(r, signMask), r);
}

// shared::pointToTriangleFactor(p_k, n_k, t_k) for the scratch's points [first, first + count),
// four at a time, each lane with its own receiver normal and target triangle: the front test,
// the clip (taken only when it keeps the whole triangle; other lanes call the shared function)
// and Lambert's contour sum of shared::pointToPolygonFactor. Lanes are assembled from scalar
// loads (_mm_setr_ps).
void pointToTriangleFactors(const FarFieldScratch& s, float* out) {
    const int count = int(s.points.size());
    const float eps2Scalar = shared::planeEpsilon(1.0f) * shared::planeEpsilon(1.0f);
    const Lane zero = _mm_setzero_ps();
    const Lane eps2 = splat(eps2Scalar);
    for (int first = 0; first < count; first += 4) {
        int lane[4];
        for (int k = 0; k < 4; ++k)
            lane[k] = first + k < count ? first + k : count - 1;
        const FarFieldScratch::Point* q[4] = {&s.points[lane[0]], &s.points[lane[1]],
                                              &s.points[lane[2]], &s.points[lane[3]]};
        const auto load = [&](auto get) {
            return _mm_setr_ps(get(*q[0]), get(*q[1]), get(*q[2]), get(*q[3]));
        };
        const PatchGeometry* t[4] = {q[0]->target, q[1]->target, q[2]->target, q[3]->target};
        const PatchGeometry* r[4] = {q[0]->receiver, q[1]->receiver, q[2]->receiver,
                                     q[3]->receiver};
        const auto targets = [&](auto get) {
            return _mm_setr_ps(get(*t[0]), get(*t[1]), get(*t[2]), get(*t[3]));
        };
        const Lane px = load([](const FarFieldScratch::Point& p) { return p.position.x; });
        const Lane py = load([](const FarFieldScratch::Point& p) { return p.position.y; });
        const Lane pz = load([](const FarFieldScratch::Point& p) { return p.position.z; });
        const Lane nx = _mm_setr_ps(r[0]->normal.x, r[1]->normal.x, r[2]->normal.x, r[3]->normal.x);
        const Lane ny = _mm_setr_ps(r[0]->normal.y, r[1]->normal.y, r[2]->normal.y, r[3]->normal.y);
        const Lane nz = _mm_setr_ps(r[0]->normal.z, r[1]->normal.z, r[2]->normal.z, r[3]->normal.z);
        Lane cx[3], cy[3], cz[3];
        cx[0] = targets([](const PatchGeometry& g) { return g.a.x; });
        cy[0] = targets([](const PatchGeometry& g) { return g.a.y; });
        cz[0] = targets([](const PatchGeometry& g) { return g.a.z; });
        cx[1] = targets([](const PatchGeometry& g) { return g.b.x; });
        cy[1] = targets([](const PatchGeometry& g) { return g.b.y; });
        cz[1] = targets([](const PatchGeometry& g) { return g.b.z; });
        cx[2] = targets([](const PatchGeometry& g) { return g.c.x; });
        cy[2] = targets([](const PatchGeometry& g) { return g.c.y; });
        cz[2] = targets([](const PatchGeometry& g) { return g.c.z; });
        // In front of t: dot(t.normal, p - t.a) > 0.
        const Lane front =
            _mm_cmpgt_ps(dot3(targets([](const PatchGeometry& g) { return g.normal.x; }),
                              targets([](const PatchGeometry& g) { return g.normal.y; }),
                              targets([](const PatchGeometry& g) { return g.normal.z; }),
                              _mm_sub_ps(px, cx[0]), _mm_sub_ps(py, cy[0]), _mm_sub_ps(pz, cz[0])),
                         zero);
        Lane vx[3], vy[3], vz[3];
        Lane whole = _mm_castsi128_ps(_mm_set1_epi32(-1));
        for (int k = 0; k < 3; ++k) {
            vx[k] = _mm_sub_ps(cx[k], px);
            vy[k] = _mm_sub_ps(cy[k], py);
            vz[k] = _mm_sub_ps(cz[k], pz);
            Lane d = dot3(nx, ny, nz, vx[k], vy[k], vz[k]);
            const Lane onPlane = _mm_cmple_ps(
                _mm_mul_ps(d, d), _mm_mul_ps(eps2, dot3(vx[k], vy[k], vz[k], vx[k], vy[k], vz[k])));
            d = _mm_andnot_ps(onPlane, d);
            whole = _mm_and_ps(whole, _mm_cmpge_ps(d, zero));
        }
        Lane sum = zero;
        for (int k = 0; k < 3; ++k) {
            const int k1 = k == 2 ? 0 : k + 1;
            // e_k = corner_k+1 - corner_k, g = cross(v_k, e_k)
            const Lane ex = _mm_sub_ps(cx[k1], cx[k]);
            const Lane ey = _mm_sub_ps(cy[k1], cy[k]);
            const Lane ez = _mm_sub_ps(cz[k1], cz[k]);
            const Lane gx = _mm_sub_ps(_mm_mul_ps(vy[k], ez), _mm_mul_ps(vz[k], ey));
            const Lane gy = _mm_sub_ps(_mm_mul_ps(vz[k], ex), _mm_mul_ps(vx[k], ez));
            const Lane gz = _mm_sub_ps(_mm_mul_ps(vx[k], ey), _mm_mul_ps(vy[k], ex));
            const Lane gLength = _mm_sqrt_ps(dot3(gx, gy, gz, gx, gy, gz));
            const Lane gamma =
                atan2Lanes(gLength, dot3(vx[k], vy[k], vz[k], vx[k1], vy[k1], vz[k1]));
            const Lane term = _mm_mul_ps(gamma, _mm_div_ps(dot3(nx, ny, nz, gx, gy, gz), gLength));
            sum = _mm_add_ps(sum, select(_mm_cmpgt_ps(gLength, zero), term, zero));
        }
        // max(0, -sum / (2 pi)) = x > 0 ? x : 0, and 0 behind t.
        const Lane f = _mm_mul_ps(_mm_xor_ps(sum, splat(-0.0f)), splat(DAISY_INV_TWO_PI));
        const Lane value = _mm_and_ps(front, select(_mm_cmpgt_ps(f, zero), f, zero));
        alignas(16) float values[4];
        _mm_store_ps(values, value);
        const int frontBits = _mm_movemask_ps(front);
        const int wholeBits = _mm_movemask_ps(whole);
        for (int k = 0; k < 4 && first + k < count; ++k) {
            const bool clipped = ((frontBits >> k) & 1) != 0 && ((wholeBits >> k) & 1) == 0;
            out[first + k] = clipped
                ? shared::pointToTriangleFactor(q[k]->position, r[k]->normal, *t[k])
                : values[k];
        }
    }
}

#else

void pointToTriangleFactors(const FarFieldScratch& s, float* out) {
    for (const FarFieldScratch::Point& q : s.points)
        *out++ = shared::pointToTriangleFactor(q.position, q.receiver->normal, *q.target);
}

#endif

// max(max(length(a), length(b)), length(c)) of the shared kernel with one square root: sqrt is
// correctly rounded and monotone, so the largest root is the root of the largest square.
float longestOf(vec3 a, vec3 b, vec3 c) {
    return shared::sqrt(
        shared::max(shared::max(shared::dot(a, a), shared::dot(b, b)), shared::dot(c, c)));
}

// Appends the cells and points of shared::hybridPairFactor(level, i, j) to the scratch when no
// cell is near j (the result is then the fixed part: share times the centroid value of each far
// cell or the threePointRule of each middle one, summed in cell order) and returns true; returns
// false, appending nothing, when the pair needs the shared kernel (a near cell, L > 2). The
// prologue is that function's (the clip of i to j's front half-space, the roots, whether a root
// is one cell, the cells and their distance ratios), by the same expressions. An empty piece
// plans no cells (F = 0).
bool planHybridPair(int level, const PatchGeometry& i, const PatchGeometry& j, FarFieldScratch& s) {
    const int cells = 1 << (2 * level);
    if (cells > kMaxCellsPerRoot) return false;
    const ClippedPolygon piece = shared::clipTriangleToHalfSpace(i.a, i.b, i.c, j.a, j.normal);
    if (piece.count < 3) return true;
    const std::size_t pointMark = s.points.size();
    const std::size_t cellMark = s.cells.size();
    const vec3 jCentre = shared::patchCentroid(j);
    float jRadius = -1.0f;  // the shared kernel's, computed when first needed
    // distanceLowerBound(x) / diameter >= bound, as the shared kernel decides it. It is max(plane
    // distance, sphere distance): far by the plane alone is far by it (division by the positive
    // diameter is monotone and commutes with max), without the sphere's square root.
    const auto atLeast = [&](vec3 x, float diameter, float bound) {
        if (shared::abs(shared::dot(j.normal, x - j.a)) / diameter >= bound) return true;
        if (jRadius < 0.0f) jRadius = longestOf(j.a - jCentre, j.b - jCentre, j.c - jCentre);
        return shared::distanceLowerBound(x, j, jCentre, jRadius) / diameter >= bound;
    };
    // One cell: its centroid x (far) or threePointRule's points (middle).
    const auto addCell = [&](vec3 a, vec3 b, vec3 c, vec3 x, bool isFar, float share) {
        s.cells.push_back({share, isFar ? 1u : 3u});
        if (isFar) {
            s.points.push_back({x, &i, &j});
        } else {
            const vec3 sum = a + b + c;
            s.points.push_back({(sum + a * 3.0f) * (1.0f / 6.0f), &i, &j});
            s.points.push_back({(sum + b * 3.0f) * (1.0f / 6.0f), &i, &j});
            s.points.push_back({(sum + c * 3.0f) * (1.0f / 6.0f), &i, &j});
        }
    };
    const float levelScale = 1.0f / float(1 << level);
    for (int r = 0; r + 2 < piece.count; ++r) {
        const vec3 ra = piece.v[0];
        const vec3 rb = piece.v[r + 1];
        const vec3 rc = piece.v[r + 2];
        const float rootArea = 0.5f * shared::length(shared::cross(rb - ra, rc - ra));
        const float rootDiameter = longestOf(rb - ra, rc - rb, ra - rc);
        const vec3 rootCentre = (ra + rb + rc) * (1.0f / 3.0f);
        if (atLeast(rootCentre, rootDiameter, DAISY_FF_MID_RATIO)) {  // the root is one cell
            addCell(ra, rb, rc, rootCentre, atLeast(rootCentre, rootDiameter, DAISY_FF_FAR_RATIO),
                    rootArea * 1.0f * 1.0f / i.area);
            continue;
        }
        const float share = rootArea * levelScale * levelScale / i.area;
        const float cellDiameter = rootDiameter * levelScale;
        for (int t = 0; t < cells; ++t) {
            vec3 a = ra;
            vec3 b = rb;
            vec3 c = rc;
            shared::cellCorners(uint32_t(t), level, a, b, c);
            const vec3 x = (a + b + c) * (1.0f / 3.0f);
            if (!atLeast(x, cellDiameter, DAISY_FF_MID_RATIO)) {  // a near cell: roll back
                s.points.resize(pointMark);
                s.cells.resize(cellMark);
                return false;
            }
            addCell(a, b, c, x, atLeast(x, cellDiameter, DAISY_FF_FAR_RATIO), share);
        }
    }
    return true;
}

// shared::pairFactors (the accurate direction, reciprocity for the other entry) of the hybrid
// method for pairs[k], planned into the scratch or, where planning fails, the shared kernel's;
// facingAway tested only when `testFacing` (a candidate pair has passed it already).
void hybridPairFactors(int level, std::span<const PatchGeometry> geometry,
                       std::span<const PairIndex> pairs, bool testFacing,
                       std::span<shared::PairFactors> out, FarFieldScratch& s) {
    const int l = shared::clamp(level, 0, DAISY_MAX_QUADRATURE_LEVEL);
    s.points.clear();
    s.cells.clear();
    s.pairs.clear();
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        const PatchGeometry& i = geometry[pairs[k].i];
        const PatchGeometry& j = geometry[pairs[k].j];
        const bool swapped = shared::patchPrecedes(j, i);
        const PatchGeometry& first = swapped ? j : i;
        const PatchGeometry& second = swapped ? i : j;
        float direct = 0.0f;  // the unoccluded factor first -> second, when not planned
        bool planned = false;
        if (!(testFacing && shared::facingAway(first, second))) {
            planned = planHybridPair(l, first, second, s);
            if (!planned) direct = shared::hybridPairFactor(l, first, second);
        }
        s.pairs.push_back({planned ? uint32_t(s.cells.size()) : kNotPlanned, direct});
    }
    s.values.resize(s.points.size());
    pointToTriangleFactors(s, s.values.data());
    uint32_t cell = 0;
    std::size_t point = 0;
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        float f = s.pairs[k].direct;
        if (s.pairs[k].cellEnd != kNotPlanned) {
            float fixedPart = 0.0f;
            for (; cell < s.pairs[k].cellEnd; ++cell) {
                if (s.cells[cell].points == 3) {
                    float sum = s.values[point];
                    sum += s.values[point + 1];
                    sum += s.values[point + 2];
                    fixedPart += s.cells[cell].share * (sum * (1.0f / 3.0f));
                    point += 3;
                } else {
                    fixedPart += s.cells[cell].share * s.values[point];
                    point += 1;
                }
            }
            f = fixedPart;
        }
        const PatchGeometry& i = geometry[pairs[k].i];
        const PatchGeometry& j = geometry[pairs[k].j];
        if (shared::patchPrecedes(j, i)) {
            out[k].fji = f;
            out[k].fij = f * (j.area / i.area);
        } else {
            out[k].fij = f;
            out[k].fji = f * (i.area / j.area);
        }
    }
}

shared::PairFactors onePair(int method, int level, const PatchGeometry& i, const PatchGeometry& j,
                            bool testFacing) {
    if (method != DAISY_METHOD_HYBRID) return shared::pairFactors(method, level, i, j);
    const PatchGeometry geometry[2] = {i, j};
    const PairIndex pair{0u, 1u};
    shared::PairFactors f;
    FarFieldScratch scratch;
    hybridPairFactors(level, geometry, std::span(&pair, 1), testFacing, std::span(&f, 1), scratch);
    return f;
}

}  // namespace

shared::PairFactors pairFactorsCpu(int method, int level, const PatchGeometry& i,
                                   const PatchGeometry& j) {
    return onePair(method, level, i, j, true);
}

shared::PairFactors candidatePairFactorsCpu(int method, int level, const PatchGeometry& i,
                                            const PatchGeometry& j) {
    return onePair(method, level, i, j, false);
}

void candidateFactorsCpu(int method, int level, std::span<const PatchGeometry> geometry,
                         std::span<const PairIndex> pairs, std::span<float> fij,
                         FarFieldScratch& scratch) {
    if (method != DAISY_METHOD_HYBRID) {
        for (std::size_t k = 0; k < pairs.size(); ++k) {
            const float f =
                shared::pairFactors(method, level, geometry[pairs[k].i], geometry[pairs[k].j]).fij;
            fij[k] = f > 0.0f ? f : 0.0f;
        }
        return;
    }
    scratch.factors.resize(pairs.size());
    hybridPairFactors(level, geometry, pairs, false, scratch.factors, scratch);
    for (std::size_t k = 0; k < pairs.size(); ++k)
        fij[k] = scratch.factors[k].fij > 0.0f ? scratch.factors[k].fij : 0.0f;
}

}  // namespace daisy
