#include "radiosity/hybrid_far_field.h"

#include "core/cpu_isa.h"
#include "radiosity/hybrid_near_cells.h"
#include "shared/config.h"
#include "shared/formfactor.h"

// The lanes are GCC vector extensions, kept inline in their entry points (no vector crosses a
// call, whatever -Wpsabi says about the ABI of AVX vectors).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
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

// W floats, one per quadrature point, in GCC's generic vectors: SSE registers for W = 4 (any
// x86-64), AVX ones for W = 8 in the avx2 entry point below. Every helper is the shared
// dialect's operation (shared/prelude.h) lane by lane, with the same operand order, so each lane
// rounds as the scalar code does (no FMA: neither target enables it, so nothing is contracted).
template <int W>
struct Lanes {
    typedef float F __attribute__((vector_size(4 * W)));
    typedef int32_t I __attribute__((vector_size(4 * W)));
};

// mask ? a : b per lane, as bits (mask lanes are all ones or all zeros).
template <int W>
[[gnu::always_inline]] inline typename Lanes<W>::F select(typename Lanes<W>::I mask,
                                                          typename Lanes<W>::F a,
                                                          typename Lanes<W>::F b) {
    using I = typename Lanes<W>::I;
    using F = typename Lanes<W>::F;
    return F(((I)a & mask) | ((I)b & ~mask));
}

template <int W>
[[gnu::always_inline]] inline typename Lanes<W>::F absLanes(typename Lanes<W>::F x) {
    using I = typename Lanes<W>::I;
    using F = typename Lanes<W>::F;
    return F((I)x & 0x7fffffff);
}

// dot(a, b) = a.x * b.x + a.y * b.y + a.z * b.z, summed left to right.
template <typename F>
[[gnu::always_inline]] inline F dot3(F ax, F ay, F az, F bx, F by, F bz) {
    return (ax * bx + ay * by) + az * bz;
}

// shared::daisyAtan2 (prelude.h), step by step.
template <int W>
[[gnu::always_inline]] inline typename Lanes<W>::F atan2Lanes(typename Lanes<W>::F y,
                                                              typename Lanes<W>::F x) {
    using I = typename Lanes<W>::I;
    using F = typename Lanes<W>::F;
    const F zero = F{};
    const F ax = absLanes<W>(x);
    const F ay = absLanes<W>(y);
    const I yOverX = ay > ax;
    const F greater = select<W>(yOverX, ay, ax);  // max(ax, ay) = ay > ax ? ay : ax
    const F lesser = select<W>(ay < ax, ay, ax);  // min(ax, ay)
    const I upper = lesser > 0.414213562f * greater;
    const F num = select<W>(upper, lesser - greater, lesser);
    const F den = select<W>(upper, lesser + greater, greater);
    const F a = select<W>(den > zero, num / den, zero);
    const F z = a * a;
    F p = 8.05374449538e-2f * z - 1.38776856032e-1f;
    p = p * z + 1.99777106478e-1f;
    p = p * z - 3.33329491539e-1f;
    F r = select<W>(upper, zero + 0.785398163f, zero) + (a + (a * z) * p);
    r = select<W>(yOverX, 1.57079633f - r, r);
    r = select<W>(x < zero, 3.14159265f - r, r);
    return select<W>(y < zero, -r, r);
}

// shared::pointToTriangleFactor(p_k, n_k, t_k) for the points, W at a time, each lane with its
// own receiver normal and target triangle: the front test, the clip (the shared function's, lane
// by lane, where it cuts the triangle: a polygon of 3 or 4 corners) and Lambert's contour sum of
// shared::pointToPolygonFactor over each lane's polygon. Lanes are assembled from scalar loads.
template <int W>
[[gnu::always_inline]] inline void pointToTriangleFactorsOf(
    std::span<const FarFieldScratch::Point> points, float* out) {
    using I = typename Lanes<W>::I;
    using F = typename Lanes<W>::F;
    const int count = int(points.size());
    const float eps2 = shared::planeEpsilon(1.0f) * shared::planeEpsilon(1.0f);
    const F zero = F{};
    for (int first = 0; first < count; first += W) {
        const FarFieldScratch::Point* q[W];
        for (int k = 0; k < W; ++k)
            q[k] = &points[first + k < count ? first + k : count - 1];
        // The polygon's corners (the triangle's unless clipped; corner 3 repeats corner 0 where
        // there are 3) and how many it has.
        F px, py, pz, nx, ny, nz, tnx, tny, tnz, cx[4], cy[4], cz[4];
        I corners = I{} + 3;
        for (int k = 0; k < W; ++k) {
            const PatchGeometry& t = *q[k]->target;
            const vec3 n = q[k]->receiver->normal;
            px[k] = q[k]->position.x, py[k] = q[k]->position.y, pz[k] = q[k]->position.z;
            nx[k] = n.x, ny[k] = n.y, nz[k] = n.z;
            tnx[k] = t.normal.x, tny[k] = t.normal.y, tnz[k] = t.normal.z;
            cx[0][k] = t.a.x, cy[0][k] = t.a.y, cz[0][k] = t.a.z;
            cx[1][k] = t.b.x, cy[1][k] = t.b.y, cz[1][k] = t.b.z;
            cx[2][k] = t.c.x, cy[2][k] = t.c.y, cz[2][k] = t.c.z;
        }
        cx[3] = cx[0], cy[3] = cy[0], cz[3] = cz[0];
        // In front of t: dot(t.normal, p - t.a) > 0.
        const I front = dot3(tnx, tny, tnz, px - cx[0], py - cy[0], pz - cz[0]) > zero;
        I whole = zero == zero;
        for (int k = 0; k < 3; ++k) {
            const F vx = cx[k] - px, vy = cy[k] - py, vz = cz[k] - pz;
            F d = dot3(nx, ny, nz, vx, vy, vz);
            const I onPlane = d * d <= eps2 * dot3(vx, vy, vz, vx, vy, vz);
            d = select<W>(onPlane, zero, d);
            whole &= d >= zero;
        }
        for (int k = 0; k < W; ++k) {
            if (front[k] == 0 || whole[k] != 0) continue;
            const PatchGeometry& t = *q[k]->target;
            const ClippedPolygon poly = shared::clipTriangleToHalfSpace(
                t.a, t.b, t.c, q[k]->position, q[k]->receiver->normal);
            corners[k] = poly.count;
            for (int v = 0; v < poly.count; ++v)
                cx[v][k] = poly.v[v].x, cy[v][k] = poly.v[v].y, cz[v][k] = poly.v[v].z;
            if (poly.count == 3) cx[3][k] = cx[0][k], cy[3][k] = cy[0][k], cz[3][k] = cz[0][k];
        }
        F vx[4], vy[4], vz[4];
        for (int k = 0; k < 4; ++k) {
            vx[k] = cx[k] - px;
            vy[k] = cy[k] - py;
            vz[k] = cz[k] - pz;
        }
        const I four = corners == 4;
        bool anyFour = false;
        for (int k = 0; k < W; ++k)
            anyFour = anyFour || four[k] != 0;
        F sum = zero;
        for (int k = 0; k < (anyFour ? 4 : 3); ++k) {
            // The next corner: k + 1, or back to 0 after the last (2 of a triangle, 3 of four).
            const int k1 = k == 3 ? 0 : k + 1;
            const F nextX = k == 2 ? select<W>(four, cx[3], cx[0]) : cx[k1];
            const F nextY = k == 2 ? select<W>(four, cy[3], cy[0]) : cy[k1];
            const F nextZ = k == 2 ? select<W>(four, cz[3], cz[0]) : cz[k1];
            const F wx = k == 2 ? select<W>(four, vx[3], vx[0]) : vx[k1];
            const F wy = k == 2 ? select<W>(four, vy[3], vy[0]) : vy[k1];
            const F wz = k == 2 ? select<W>(four, vz[3], vz[0]) : vz[k1];
            // e_k = corner_k+1 - corner_k, g = cross(v_k, e_k)
            const F ex = nextX - cx[k], ey = nextY - cy[k], ez = nextZ - cz[k];
            const F gx = vy[k] * ez - vz[k] * ey;
            const F gy = vz[k] * ex - vx[k] * ez;
            const F gz = vx[k] * ey - vy[k] * ex;
            const F g2 = dot3(gx, gy, gz, gx, gy, gz);
            F gLength;
            for (int l = 0; l < W; ++l)
                gLength[l] = shared::sqrt(g2[l]);
            const F gamma = atan2Lanes<W>(gLength, dot3(vx[k], vy[k], vz[k], wx, wy, wz));
            const F term = gamma * (dot3(nx, ny, nz, gx, gy, gz) / gLength);
            const I edge = k == 3 ? four : zero == zero;
            sum = sum + select<W>(edge & (gLength > zero), term, zero);
        }
        // max(0, -sum / (2 pi)) = x > 0 ? x : 0, and 0 behind t or when the clip left no polygon.
        const F f = -sum * DAISY_INV_TWO_PI;
        const F value = select<W>(front & (corners >= 3), select<W>(f > zero, f, zero), zero);
        for (int k = 0; k < W && first + k < count; ++k)
            out[first + k] = value[k];
    }
}

void pointToTriangleFactorsSse(std::span<const FarFieldScratch::Point> points, float* out) {
    pointToTriangleFactorsOf<4>(points, out);
}

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target("avx2"))) void pointToTriangleFactorsAvx2(
    std::span<const FarFieldScratch::Point> points, float* out) {
    pointToTriangleFactorsOf<8>(points, out);
}

// AVX-512 has fused multiply-add, which GCC would contract a * b + c into (one rounding where
// the shared kernel has two): this file is compiled with -ffp-contract=off (CMakeLists.txt).
__attribute__((target("avx512f"))) void pointToTriangleFactorsAvx512(
    std::span<const FarFieldScratch::Point> points, float* out) {
    pointToTriangleFactorsOf<16>(points, out);
}
#endif

// max(max(length(a), length(b)), length(c)) of the shared kernel with one square root: sqrt is
// correctly rounded and monotone, so the largest root is the root of the largest square.
float longestOf(vec3 a, vec3 b, vec3 c) {
    return shared::sqrt(
        shared::max(shared::max(shared::dot(a, a), shared::dot(b, b)), shared::dot(c, c)));
}

FarFieldPatch farFieldPatch(const PatchGeometry& t) {
    const vec3 centroid = shared::patchCentroid(t);
    return {centroid, longestOf(t.a - centroid, t.b - centroid, t.c - centroid),
            0.5f * shared::length(shared::cross(t.b - t.a, t.c - t.a)),
            longestOf(t.b - t.a, t.c - t.b, t.a - t.c)};
}

bool same(vec3 x, vec3 y) {
    return x.x == y.x && x.y == y.y && x.z == y.z;
}

// Appends the cells and points of shared::hybridPairFactorWith(level, i, j, true) to the scratch
// when no cell is near j (the result is then the fixed part: share times the centroid value of each
// far cell or the threePointRule of each middle one, summed in cell order) and returns true;
// returns false, appending nothing, when the pair needs the shared kernel (a near cell, L > 2). The
// prologue is that function's (the clip of i to j's front half-space, the roots, whether a root
// is one cell, the cells and their distance ratios), by the same expressions, with pi and pj
// (farFieldPatch of i and j) for what depends on a whole patch alone: j's centre and radius, and
// i's root when the piece is i itself (wholly in front of j: clipTriangleToHalfSpace returns its
// corners). An empty piece plans no cells (F = 0).
bool planHybridPair(int level, const PatchGeometry& i, const PatchGeometry& j,
                    const FarFieldPatch& pi, const FarFieldPatch& pj, FarFieldScratch& s) {
    const int cells = 1 << (2 * level);
    if (cells > kMaxCellsPerRoot) return false;
    const ClippedPolygon piece = shared::clipTriangleToHalfSpace(i.a, i.b, i.c, j.a, j.normal);
    if (piece.count < 3) return true;
    const bool whole =
        piece.count == 3 && same(piece.v[0], i.a) && same(piece.v[1], i.b) && same(piece.v[2], i.c);
    const std::size_t pointMark = s.points.size();
    const std::size_t cellMark = s.cells.size();
    // distanceLowerBound(x) / diameter >= bound, as the shared kernel decides it. It is max(plane
    // distance, sphere distance): far by the plane alone is far by it (division by the positive
    // diameter is monotone and commutes with max), without the sphere (nor pj's cache line).
    const auto atLeast = [&](vec3 x, float diameter, float bound) {
        if (shared::abs(shared::dot(j.normal, x - j.a)) / diameter >= bound) return true;
        return shared::distanceLowerBound(x, j, pj.centroid, pj.radius) / diameter >= bound;
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
        const float rootArea =
            whole ? pi.rootArea : 0.5f * shared::length(shared::cross(rb - ra, rc - ra));
        const float rootDiameter = whole ? pi.rootDiameter : longestOf(rb - ra, rc - rb, ra - rc);
        const vec3 rootCentre = whole ? pi.centroid : (ra + rb + rc) * (1.0f / 3.0f);
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
// method for pairs[k], planned into the scratch or, where planning fails, the shared kernel's
// refined to `relativeTolerance`; facingAway tested only when `testFacing` (a candidate pair has
// passed it already).
void hybridPairFactors(int level, std::span<const PatchGeometry> geometry,
                       std::span<const FarFieldPatch> patches, std::span<const PairIndex> pairs,
                       bool testFacing, std::span<shared::PairFactors> out, FarFieldScratch& s,
                       float relativeTolerance) {
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
        const uint32_t firstIndex = swapped ? pairs[k].j : pairs[k].i;
        const uint32_t secondIndex = swapped ? pairs[k].i : pairs[k].j;
        float direct = 0.0f;  // the unoccluded factor first -> second, when not planned
        bool planned = false;
        if (!(testFacing && shared::facingAway(first, second))) {
            planned =
                planHybridPair(l, first, second, patches[firstIndex], patches[secondIndex], s);
            if (!planned) direct = hybridNearPairFactor(l, first, second, relativeTolerance, s);
        }
        s.pairs.push_back({planned ? uint32_t(s.cells.size()) : kNotPlanned, direct});
    }
    s.values.resize(s.points.size());
    pointToTriangleFactors(s.points, s.values.data());
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
    const FarFieldPatch patches[2] = {farFieldPatch(i), farFieldPatch(j)};
    const PairIndex pair{0u, 1u};
    shared::PairFactors f;
    FarFieldScratch scratch;
    hybridPairFactors(level, geometry, patches, std::span(&pair, 1), testFacing, std::span(&f, 1),
                      scratch, DAISY_FF_REL_TOL);
    return f;
}

}  // namespace

// The widest of the above that cpuIsa() allows (core/cpu_isa.h: DAISY_ISA picks a narrower one).
void pointToTriangleFactors(std::span<const FarFieldScratch::Point> points, float* out) {
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
    if (cpuIsa() == CpuIsa::Avx512) {
        pointToTriangleFactorsAvx512(points, out);
        return;
    }
    if (cpuIsa() == CpuIsa::Avx2) {
        pointToTriangleFactorsAvx2(points, out);
        return;
    }
#endif
    pointToTriangleFactorsSse(points, out);
}

shared::PairFactors pairFactorsCpu(int method, int level, const PatchGeometry& i,
                                   const PatchGeometry& j) {
    return onePair(method, level, i, j, true);
}

shared::PairFactors candidatePairFactorsCpu(int method, int level, const PatchGeometry& i,
                                            const PatchGeometry& j) {
    return onePair(method, level, i, j, false);
}

std::vector<FarFieldPatch> farFieldPatches(std::span<const PatchGeometry> geometry) {
    std::vector<FarFieldPatch> patches;
    patches.reserve(geometry.size());
    for (const PatchGeometry& t : geometry)
        patches.push_back(farFieldPatch(t));
    return patches;
}

void candidateFactorsCpu(int method, int level, std::span<const PatchGeometry> geometry,
                         std::span<const FarFieldPatch> patches, std::span<const PairIndex> pairs,
                         std::span<shared::PairFactors> out, FarFieldScratch& scratch,
                         float relativeTolerance) {
    if (method != DAISY_METHOD_HYBRID) {
        for (std::size_t k = 0; k < pairs.size(); ++k)
            out[k] = shared::pairFactors(method, level, geometry[pairs[k].i], geometry[pairs[k].j]);
    } else {
        hybridPairFactors(level, geometry, patches, pairs, false, out, scratch, relativeTolerance);
    }
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        out[k].fij = out[k].fij > 0.0f ? out[k].fij : 0.0f;
        out[k].fji = out[k].fji > 0.0f ? out[k].fji : 0.0f;
    }
}

}  // namespace daisy
