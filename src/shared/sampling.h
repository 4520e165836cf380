// Deterministic stratified sampling for the ray-cast parts of the form-factor methods: points on a
// patch (visibility rays, stochastic ray origins) and cosine-weighted directions. Every function
// is a pure function of (seed, index, count, geometry), so all backends draw the same samples.
#ifndef DAISY_SHARED_SAMPLING_H
#define DAISY_SHARED_SAMPLING_H

#include "config.h"
#include "gpu_types.h"
#include "prelude.h"
#include "rng.h"

DAISY_SHARED_BEGIN

// Midpoint subdivision of the triangle (a, b, c) into 4 similar children, replacing the corners
// by those of child d: 0, 1, 2 keep corner a, b, c; 3 is the middle (inverted) triangle. Each
// child has a quarter of the area. Used by the stratified sampler and the quadrature cells.
DAISY_HD void selectSubTriangle(uint d, DAISY_INOUT(vec3) a, DAISY_INOUT(vec3) b,
                                DAISY_INOUT(vec3) c) {
    vec3 ab = (a + b) * 0.5f;
    vec3 bc = (b + c) * 0.5f;
    vec3 ca = (c + a) * 0.5f;
    if (d == 0u) {
        b = ab;
        c = ca;
    } else if (d == 1u) {
        a = ab;
        c = bc;
    } else if (d == 2u) {
        a = ca;
        b = bc;
    } else {
        a = bc;
        b = ca;
        c = ab;
    }
}

// Uniform point in the triangle (a, b, c) from u in [0, 1)^2: the area-preserving square-root
// warp (Osada, Funkhouser, Chazelle & Dobkin 2002, "Shape distributions", ACM TOG 21(4)).
DAISY_HD vec3 uniformPointOnTriangle(vec3 a, vec3 b, vec3 c, vec2 u) {
    float su = sqrt(u.x);
    return a * (1.0f - su) + b * (su * (1.0f - u.y)) + c * (su * u.y);
}

// Number of base-4 digits (subdivision levels) that give `count` points a cell each:
// the smallest m with 4^m >= count, at most 15 (2 bits a level in a uint).
DAISY_HD int stratificationLevels(int count) {
    int m = 0;
    while (m < 15 && (1 << (2 * m)) < count)
        ++m;
    return m;
}

// The per-(seed, count) constants of stratifiedPointOnTriangle, hoisted out of the loop over k.
struct TriangleSampleStream {
    int levels;  // stratificationLevels(count)
    uint scramble;  // digit scrambling, pcgHash(seed)
    uint jitterKey;  // key of the in-cell jitter hashes
};

DAISY_HD TriangleSampleStream makeTriangleSampleStream(uint seed, int count) {
    TriangleSampleStream s;
    s.levels = stratificationLevels(count);
    s.scramble = pcgHash(seed);
    s.jitterKey = pcgHash(pcgHash(seed + 0x68bc21ebu));
    return s;
}

// Point k of the stream's `count` (0 <= k < count) on triangle t: the triangular van der Corput
// sequence (Basu & Owen 2015, "Low discrepancy constructions in the triangle", SIAM J. Numer.
// Anal. 53(2)) with digits scrambled by the seed, jittered uniformly in its final cell. The
// base-4 digits of k, least significant first, pick the midpoint-subdivision child at each level,
// so the first `count` points fall in distinct cells of level ceil(log4 count) and every prefix is
// spread evenly; for count = 4^m each of the 4^m cells holds exactly one point.
DAISY_HD vec3 streamPointOnTriangle(DAISY_IN(TriangleSampleStream) s, int k,
                                    DAISY_IN(PatchGeometry) t) {
    uint q = uint(k);
    vec3 a = t.a;
    vec3 b = t.b;
    vec3 c = t.c;
    for (int l = 0; l < s.levels; ++l) {
        uint d = ((q >> uint(2 * l)) ^ (s.scramble >> uint(2 * l))) & 3u;
        selectSubTriangle(d, a, b, c);
    }
    vec2 u = vec2(uintToUnitFloat(pcgHash((2u * q) ^ s.jitterKey)),
                  uintToUnitFloat(pcgHash((2u * q + 1u) ^ s.jitterKey)));
    return uniformPointOnTriangle(a, b, c, u);
}

// Point k of `count` on triangle t for `seed`: streamPointOnTriangle of that stream.
DAISY_HD vec3 stratifiedPointOnTriangle(uint seed, int k, int count, DAISY_IN(PatchGeometry) t) {
    return streamPointOnTriangle(makeTriangleSampleStream(seed, count), k, t);
}

// Sample s of `count` of Kensler's correlated multi-jittered pattern `seed` in [0, 1)^2 (Kensler
// 2013, "Correlated Multi-Jittered Sampling", Pixar TM 13-01, final cmj() with aspect 1):
// stratified in both 1D projections and in 2D for any count >= 1; the sample order is itself
// permuted, so it is uncorrelated with the index digits stratifiedPointOnTriangle uses.
DAISY_HD vec2 correlatedMultiJitter(int s, int count, uint seed) {
    uint n = uint(count);
    uint m = max(1u, uint(sqrt(float(count))));
    uint rows = (n + m - 1u) / m;
    uint sp = permuteIndex(uint(s), n, seed * 0x51633e2du);
    uint sx = permuteIndex(sp % m, m, seed * 0x68bc21ebu);
    uint sy = permuteIndex(sp / m, rows, seed * 0x02e5be93u);
    float jx = kenslerRandFloat(sp, seed * 0x967a889bu);
    float jy = kenslerRandFloat(sp, seed * 0x368cc8b7u);
    float x = (float(sx) + (float(sy) + jx) / float(rows)) / float(m);
    float y = (float(sp) + jy) / float(n);
    return vec2(min(x, 0.99999994f), min(y, 0.99999994f));
}

// Unit vectors t1, t2 completing the unit normal n to a right-handed orthonormal basis (Duff et
// al. 2017, "Building an Orthonormal Basis, Revisited", JCGT 6(1)).
DAISY_HD void orthonormalBasis(vec3 n, DAISY_INOUT(vec3) t1, DAISY_INOUT(vec3) t2) {
    float s = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (s + n.z);
    float b = n.x * n.y * a;
    t1 = vec3(1.0f + s * n.x * n.x * a, s * b, -s * n.x);
    t2 = vec3(b, s + n.y * n.y * a, -n.y);
}

// Cosine-weighted direction about the unit normal n from u in [0, 1)^2 (pdf cos(theta)/pi):
// Malley's method, lifting the concentric disk map (Shirley & Chiu 1997, "A Low Distortion Map
// Between Disk and Square", JGT 2(3)), which keeps u's stratification.
DAISY_HD vec3 cosineDirection(vec3 n, vec2 u) {
    float sx = 2.0f * u.x - 1.0f;
    float sy = 2.0f * u.y - 1.0f;
    float r = 0.0f;
    float phi = 0.0f;
    if (sx != 0.0f || sy != 0.0f) {
        if (abs(sx) > abs(sy)) {
            r = sx;
            phi = 0.25f * DAISY_PI * (sy / sx);
        } else {
            r = sy;
            phi = 0.5f * DAISY_PI - 0.25f * DAISY_PI * (sx / sy);
        }
    }
    float dx = r * cos(phi);
    float dy = r * sin(phi);
    float dz = sqrt(max(0.0f, 1.0f - dx * dx - dy * dy));
    vec3 t1;
    vec3 t2;
    orthonormalBasis(n, t1, t2);
    return normalize(t1 * dx + t2 * dy + n * dz);
}

// Shadow-ray end points k of `count` for the unordered pair {i, j} with seed pairSeed(i, j, s):
// pi on i and pj on j, each stratified over its patch. The pair's patchPrecedes-first patch
// takes stream 0 with index k, the other stream 1 with a permuted index (decorrelating the
// pairing of cells), so swapping the arguments swaps the outputs and nothing else: backends and
// call orders agree. Points lie on the patches; offsetting them off the surface is the caller's.
// A loop over k may hoist the two makeTriangleSampleStream calls and permuteIndex's seed.
DAISY_HD void visibilitySamplePair(uint pairSeedValue, int k, int count, DAISY_IN(PatchGeometry) i,
                                   DAISY_IN(PatchGeometry) j, DAISY_INOUT(vec3) pi,
                                   DAISY_INOUT(vec3) pj) {
    TriangleSampleStream first = makeTriangleSampleStream(streamSeed(pairSeedValue, 0u), count);
    TriangleSampleStream second = makeTriangleSampleStream(streamSeed(pairSeedValue, 1u), count);
    int kPermuted = int(permuteIndex(uint(k), uint(count), streamSeed(pairSeedValue, 2u)));
    if (patchPrecedes(j, i)) {
        pj = streamPointOnTriangle(first, k, j);
        pi = streamPointOnTriangle(second, kPermuted, i);
    } else {
        pi = streamPointOnTriangle(first, k, i);
        pj = streamPointOnTriangle(second, kPermuted, j);
    }
}

// Ray k of `count` leaving patch i for the stochastic method (seed = patchSeed(i, s)): origin
// stratified on i, direction cosine-weighted about i's normal with CMJ-stratified u, so
// F_ij = (hits on j) / count estimates the form factor with visibility. The origin lies on i;
// the caller offsets it or sets the ray's t_near.
DAISY_HD void stochasticRay(uint patchSeedValue, int k, int count, DAISY_IN(PatchGeometry) i,
                            DAISY_INOUT(vec3) origin, DAISY_INOUT(vec3) direction) {
    origin = stratifiedPointOnTriangle(streamSeed(patchSeedValue, 0u), k, count, i);
    vec2 u = correlatedMultiJitter(k, count, streamSeed(patchSeedValue, 1u));
    direction = cosineDirection(i.normal, u);
}

DAISY_SHARED_END

#endif  // DAISY_SHARED_SAMPLING_H
