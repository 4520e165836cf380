#include "radiosity/hybrid_far_field.h"

#include "shared/config.h"
#include "shared/formfactor.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace daisy {
namespace {

using shared::ClippedPolygon;
using shared::PatchGeometry;
using shared::vec3;

// Cells per root triangle the fast path takes (L <= 2); finer levels are the shared kernel's.
constexpr int kMaxCellsPerRoot = 16;

// Points as structure of arrays. Lanes are assembled from scalar loads (_mm_setr_ps), not one
// vector load: the points were just written as scalars, and a vector load of them would wait for
// the stores to drain (no store-to-load forwarding across them).
struct PointArrays {
    float x[2 * 3 * kMaxCellsPerRoot];
    float y[2 * 3 * kMaxCellsPerRoot];
    float z[2 * 3 * kMaxCellsPerRoot];
    int count = 0;
    void push(vec3 p) {
        x[count] = p.x;
        y[count] = p.y;
        z[count] = p.z;
        ++count;
    }
    vec3 at(int k) const { return vec3(x[k], y[k], z[k]); }
};

#if defined(__SSE2__)

// Four floats, one per quadrature cell. Every helper is the shared dialect's operation
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

// shared::pointToTriangleFactor(points[k], n, t) for every point, four at a time: the front
// test, the clip (taken only when it keeps the whole triangle; other lanes call the shared
// function) and Lambert's contour sum of shared::pointToPolygonFactor.
void pointToTriangleFactors(const PointArrays& points, vec3 n, const PatchGeometry& t, float* out) {
    const int count = points.count;
    const vec3 corner[3] = {t.a, t.b, t.c};
    const vec3 edge[3] = {t.b - t.a, t.c - t.b, t.a - t.c};
    const float eps2Scalar = shared::planeEpsilon(1.0f) * shared::planeEpsilon(1.0f);
    const Lane zero = _mm_setzero_ps();
    const Lane eps2 = splat(eps2Scalar);
    const Lane nx = splat(n.x), ny = splat(n.y), nz = splat(n.z);
    for (int first = 0; first < count; first += 4) {
        int lane[4];
        for (int k = 0; k < 4; ++k)
            lane[k] = first + k < count ? first + k : count - 1;
        const Lane px =
            _mm_setr_ps(points.x[lane[0]], points.x[lane[1]], points.x[lane[2]], points.x[lane[3]]);
        const Lane py =
            _mm_setr_ps(points.y[lane[0]], points.y[lane[1]], points.y[lane[2]], points.y[lane[3]]);
        const Lane pz =
            _mm_setr_ps(points.z[lane[0]], points.z[lane[1]], points.z[lane[2]], points.z[lane[3]]);
        // In front of t: dot(t.normal, p - t.a) > 0.
        const Lane front =
            _mm_cmpgt_ps(dot3(splat(t.normal.x), splat(t.normal.y), splat(t.normal.z),
                              _mm_sub_ps(px, splat(t.a.x)), _mm_sub_ps(py, splat(t.a.y)),
                              _mm_sub_ps(pz, splat(t.a.z))),
                         zero);
        Lane vx[3], vy[3], vz[3];
        Lane whole = _mm_castsi128_ps(_mm_set1_epi32(-1));
        for (int k = 0; k < 3; ++k) {
            vx[k] = _mm_sub_ps(splat(corner[k].x), px);
            vy[k] = _mm_sub_ps(splat(corner[k].y), py);
            vz[k] = _mm_sub_ps(splat(corner[k].z), pz);
            Lane s = dot3(nx, ny, nz, vx[k], vy[k], vz[k]);
            const Lane onPlane = _mm_cmple_ps(
                _mm_mul_ps(s, s), _mm_mul_ps(eps2, dot3(vx[k], vy[k], vz[k], vx[k], vy[k], vz[k])));
            s = _mm_andnot_ps(onPlane, s);
            whole = _mm_and_ps(whole, _mm_cmpge_ps(s, zero));
        }
        Lane sum = zero;
        for (int k = 0; k < 3; ++k) {
            const int k1 = k == 2 ? 0 : k + 1;
            const Lane ex = splat(edge[k].x), ey = splat(edge[k].y), ez = splat(edge[k].z);
            // g = cross(v_k, e_k)
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
            out[first + k] =
                clipped ? shared::pointToTriangleFactor(points.at(first + k), n, t) : values[k];
        }
    }
}

#else

void pointToTriangleFactors(const PointArrays& points, vec3 n, const PatchGeometry& t, float* out) {
    for (int k = 0; k < points.count; ++k)
        out[k] = shared::pointToTriangleFactor(points.at(k), n, t);
}

#endif

// max(max(length(a), length(b)), length(c)) of the shared kernel with one square root: sqrt is
// correctly rounded and monotone, so the largest root is the root of the largest square.
float longestOf(vec3 a, vec3 b, vec3 c) {
    return shared::sqrt(
        shared::max(shared::max(shared::dot(a, a), shared::dot(b, b)), shared::dot(c, c)));
}

}  // namespace

// The prologue is shared::hybridPairFactor's (the clip of i to j's front half-space, the roots,
// the cells and their distance ratios), computed by the same expressions. When no cell is near
// (ratio < DAISY_FF_MID_RATIO), that function's result is its fixed part: share times the
// centroid value of each far cell or the threePointRule of each middle one, summed in cell
// order, which is what this sums from the vectorised point values.
float hybridPairFactorCpu(int level, const PatchGeometry& i, const PatchGeometry& j) {
    const int cells = 1 << (2 * level);
    if (cells > kMaxCellsPerRoot) return shared::hybridPairFactor(level, i, j);
    const ClippedPolygon piece = shared::clipTriangleToHalfSpace(i.a, i.b, i.c, j.a, j.normal);
    if (piece.count < 3) return 0.0f;
    const vec3 jCentre = shared::patchCentroid(j);
    float jRadius = -1.0f;  // the shared kernel's, computed when first needed
    const float levelScale = 1.0f / float(1 << level);
    PointArrays points;  // 1 a far cell, 3 a middle one
    bool middle[2 * kMaxCellsPerRoot];
    float share[2];
    for (int r = 0; r + 2 < piece.count; ++r) {
        const vec3 ra = piece.v[0];
        const vec3 rb = piece.v[r + 1];
        const vec3 rc = piece.v[r + 2];
        const float rootArea = 0.5f * shared::length(shared::cross(rb - ra, rc - ra));
        const float rootDiameter = longestOf(rb - ra, rc - rb, ra - rc);
        share[r] = rootArea * levelScale * levelScale / i.area;
        for (int t = 0; t < cells; ++t) {
            vec3 a = ra;
            vec3 b = rb;
            vec3 c = rc;
            shared::cellCorners(uint32_t(t), level, a, b, c);
            const vec3 x = (a + b + c) * (1.0f / 3.0f);
            // distanceLowerBound is max(plane distance, sphere distance): far by the plane alone
            // is far by it (division by the positive diameter is monotone), without its sqrt.
            const float cellDiameter = rootDiameter * levelScale;
            const float planeRatio = shared::abs(shared::dot(j.normal, x - j.a)) / cellDiameter;
            bool isFar = planeRatio >= DAISY_FF_FAR_RATIO;
            if (!isFar) {
                if (jRadius < 0.0f)
                    jRadius = longestOf(j.a - jCentre, j.b - jCentre, j.c - jCentre);
                const float ratio =
                    shared::distanceLowerBound(x, j, jCentre, jRadius) / cellDiameter;
                if (!(ratio >= DAISY_FF_MID_RATIO)) return shared::hybridPairFactor(level, i, j);
                isFar = ratio >= DAISY_FF_FAR_RATIO;
            }
            middle[r * cells + t] = !isFar;
            if (isFar) {
                points.push(x);
            } else {  // threePointRule's points
                const vec3 sum = a + b + c;
                points.push((sum + a * 3.0f) * (1.0f / 6.0f));
                points.push((sum + b * 3.0f) * (1.0f / 6.0f));
                points.push((sum + c * 3.0f) * (1.0f / 6.0f));
            }
        }
    }
    float values[2 * 3 * kMaxCellsPerRoot];
    pointToTriangleFactors(points, i.normal, j, values);
    float fixedPart = 0.0f;
    const int cellCount = (piece.count - 2) * cells;
    for (int cell = 0, k = 0; cell < cellCount; ++cell) {
        if (middle[cell]) {
            float sum = values[k];
            sum += values[k + 1];
            sum += values[k + 2];
            fixedPart += share[cell >> (2 * level)] * (sum * (1.0f / 3.0f));
            k += 3;
        } else {
            fixedPart += share[cell >> (2 * level)] * values[k];
            k += 1;
        }
    }
    return fixedPart;
}

namespace {

// shared::pairFactors for the hybrid method: the accurate direction, reciprocity for the other
// entry; facingAway tested only when `testFacing` (a candidate pair has passed it already).
shared::PairFactors hybridPairFactorsCpu(int level, const PatchGeometry& i, const PatchGeometry& j,
                                         bool testFacing) {
    const int l = shared::clamp(level, 0, DAISY_MAX_QUADRATURE_LEVEL);
    const auto unoccluded = [&](const PatchGeometry& p, const PatchGeometry& q) {
        return testFacing && shared::facingAway(p, q) ? 0.0f : hybridPairFactorCpu(l, p, q);
    };
    shared::PairFactors f;
    if (shared::patchPrecedes(j, i)) {
        f.fji = unoccluded(j, i);
        f.fij = f.fji * (j.area / i.area);
    } else {
        f.fij = unoccluded(i, j);
        f.fji = f.fij * (i.area / j.area);
    }
    return f;
}

}  // namespace

shared::PairFactors pairFactorsCpu(int method, int level, const PatchGeometry& i,
                                   const PatchGeometry& j) {
    if (method != DAISY_METHOD_HYBRID) return shared::pairFactors(method, level, i, j);
    return hybridPairFactorsCpu(level, i, j, true);
}

shared::PairFactors candidatePairFactorsCpu(int method, int level, const PatchGeometry& i,
                                            const PatchGeometry& j) {
    if (method != DAISY_METHOD_HYBRID) return shared::pairFactors(method, level, i, j);
    return hybridPairFactorsCpu(level, i, j, false);
}

}  // namespace daisy
