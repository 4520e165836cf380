// Sampling and hashing of src/shared/sampling.h and rng.h: points stay on their patch, the
// triangle sequence is stratified (one point per midpoint-subdivision cell, Basu & Owen 2015),
// CMJ is stratified in both projections (Kensler 2013), cosine directions have the analytic
// moments of the cos(theta)/pi density, and everything is deterministic and order independent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "shared/sampling.h"
#include "verify/closed_forms.h"

namespace daisy::shared {
namespace {

// Barycentric coordinates (of a, b, c) of p in the plane of t, in double.
void barycentric(const PatchGeometry& t, vec3 p, double w[3]) {
    vec3 n = cross(t.b - t.a, t.c - t.a);
    double nn = dot(n, n);
    w[1] = dot(cross(p - t.a, t.c - t.a), n) / nn;
    w[2] = dot(cross(t.b - t.a, p - t.a), n) / nn;
    w[0] = 1.0 - w[1] - w[2];
}

// The level-`levels` midpoint-subdivision cell of t holding p, as selectSubTriangle digits
// (2 bits a level, least significant first).
uint cellOf(const PatchGeometry& t, vec3 p, int levels) {
    double w[3];
    barycentric(t, p, w);
    uint code = 0;
    for (int l = 0; l < levels; ++l) {
        uint d;
        double next[3];
        if (w[0] > 0.5) {
            d = 0;
            next[1] = 2 * w[1], next[2] = 2 * w[2], next[0] = 1 - next[1] - next[2];
        } else if (w[1] > 0.5) {
            d = 1;
            next[0] = 2 * w[0], next[2] = 2 * w[2], next[1] = 1 - next[0] - next[2];
        } else if (w[2] > 0.5) {
            d = 2;
            next[0] = 2 * w[0], next[1] = 2 * w[1], next[2] = 1 - next[0] - next[1];
        } else {
            d = 3;  // the middle child (bc, ca, ab)
            next[0] = 1 - 2 * w[0], next[1] = 1 - 2 * w[1], next[2] = 1 - 2 * w[2];
        }
        code |= d << (2 * l);
        std::copy(next, next + 3, w);
    }
    return code;
}

const PatchGeometry kTriangle =
    makePatchGeometry({0.2f, -1, 3}, {2.5f, 0.5f, 3.5f}, {-0.5f, 1.5f, 2});

TEST(SamplingTriangle, PointsLieOnTheTriangle) {
    for (uint seed : {0u, 1u, 0xdeadbeefu}) {
        for (int count : {1, 3, 10, 64, 1000}) {
            for (int k = 0; k < count; ++k) {
                vec3 p = stratifiedPointOnTriangle(seed, k, count, kTriangle);
                double w[3];
                barycentric(kTriangle, p, w);
                EXPECT_GE(std::min({w[0], w[1], w[2]}), -1e-6);
                EXPECT_NEAR(dot(kTriangle.normal, p - kTriangle.a), 0.0, 1e-5);
            }
        }
    }
}

TEST(SamplingTriangle, PowerOfFourCountsFillEveryCellOnce) {
    for (uint seed : {7u, 12345u}) {
        for (int levels : {1, 2, 3}) {
            int count = 1 << (2 * levels);
            std::set<uint> cells;
            for (int k = 0; k < count; ++k) {
                cells.insert(cellOf(kTriangle, stratifiedPointOnTriangle(seed, k, count, kTriangle),
                                    levels));
            }
            EXPECT_EQ(int(cells.size()), count) << "levels " << levels << ", seed " << seed;
        }
    }
}

TEST(SamplingTriangle, OtherCountsAreBalanced) {
    // 10 points: distinct level-2 cells, and each level-1 quarter holds 2 or 3 of them.
    const int count = 10;
    std::set<uint> cells;
    int quarter[4] = {0, 0, 0, 0};
    for (int k = 0; k < count; ++k) {
        vec3 p = stratifiedPointOnTriangle(99u, k, count, kTriangle);
        cells.insert(cellOf(kTriangle, p, 2));
        quarter[cellOf(kTriangle, p, 1)] += 1;
    }
    EXPECT_EQ(int(cells.size()), count);
    for (int q : quarter) {
        EXPECT_GE(q, 2);
        EXPECT_LE(q, 3);
    }
}

TEST(SamplingTriangle, HoistedStreamGivesTheSamePoints) {
    TriangleSampleStream stream = makeTriangleSampleStream(31u, 10);
    for (int k = 0; k < 10; ++k) {
        vec3 p = streamPointOnTriangle(stream, k, kTriangle);
        vec3 q = stratifiedPointOnTriangle(31u, k, 10, kTriangle);
        EXPECT_EQ(p.x, q.x);
        EXPECT_EQ(p.y, q.y);
        EXPECT_EQ(p.z, q.z);
    }
}

TEST(SamplingTriangle, Deterministic) {
    for (int k = 0; k < 16; ++k) {
        vec3 p = stratifiedPointOnTriangle(5u, k, 16, kTriangle);
        vec3 q = stratifiedPointOnTriangle(5u, k, 16, kTriangle);
        EXPECT_EQ(p.x, q.x);
        EXPECT_EQ(p.y, q.y);
        EXPECT_EQ(p.z, q.z);
    }
    vec3 p = stratifiedPointOnTriangle(5u, 3, 16, kTriangle);
    vec3 q = stratifiedPointOnTriangle(6u, 3, 16, kTriangle);
    EXPECT_NE(distance(p, q), 0.0f);
}

TEST(SamplingRng, PcgHashMatchesTheReference) {
    // Values of Jarzynski & Olano 2020's pcg_hash, computed independently (Python, 32-bit wrap):
    // every backend must reproduce them bit for bit.
    EXPECT_EQ(pcgHash(0u), 0x07bb2fe2u);
    EXPECT_EQ(pcgHash(1u), 0xa8beea3cu);
    EXPECT_EQ(pcgHash(42u), 0x48f432ffu);
    EXPECT_EQ(pcgHash(0xffffffffu), 0xe62a4902u);
}

TEST(SamplingRng, PairSeedIsSymmetricAndSeedDependent) {
    EXPECT_EQ(pairSeed(3u, 17u, 42u), pairSeed(17u, 3u, 42u));
    EXPECT_NE(pairSeed(3u, 17u, 42u), pairSeed(3u, 17u, 43u));
    EXPECT_NE(pairSeed(3u, 17u, 42u), pairSeed(3u, 18u, 42u));
    EXPECT_NE(pairSeed(3u, 17u, 42u), pairSeed(4u, 17u, 42u));
    EXPECT_NE(patchSeed(3u, 42u), patchSeed(4u, 42u));
}

TEST(SamplingRng, PermuteIndexIsABijection) {
    for (uint l : {1u, 2u, 7u, 64u, 1000u}) {
        std::vector<bool> hit(l, false);
        for (uint i = 0; i < l; ++i) {
            uint image = permuteIndex(i, l, 0x1234567u);
            ASSERT_LT(image, l);
            EXPECT_FALSE(hit[image]);
            hit[image] = true;
        }
    }
}

TEST(SamplingVisibility, SamePairsEitherOrderAndStratifiedOnBoth) {
    PatchGeometry other = makePatchGeometry({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    const int count = 16;
    uint seed = pairSeed(4u, 9u, 1u);
    std::set<uint> cellsI;
    std::set<uint> cellsJ;
    for (int k = 0; k < count; ++k) {
        vec3 pi, pj, qj, qi;
        visibilitySamplePair(seed, k, count, kTriangle, other, pi, pj);
        visibilitySamplePair(seed, k, count, other, kTriangle, qj, qi);
        EXPECT_EQ(pi.x, qi.x);
        EXPECT_EQ(pi.y, qi.y);
        EXPECT_EQ(pi.z, qi.z);
        EXPECT_EQ(pj.x, qj.x);
        EXPECT_EQ(pj.y, qj.y);
        EXPECT_EQ(pj.z, qj.z);
        cellsI.insert(cellOf(kTriangle, pi, 2));
        cellsJ.insert(cellOf(other, pj, 2));
    }
    EXPECT_EQ(int(cellsI.size()), count);
    EXPECT_EQ(int(cellsJ.size()), count);
}

TEST(SamplingDirections, CorrelatedMultiJitterIsStratifiedInBothProjections) {
    for (int count : {10, 64, 100}) {
        std::set<int> xs;
        std::set<int> ys;
        for (int s = 0; s < count; ++s) {
            vec2 u = correlatedMultiJitter(s, count, 77u);
            ASSERT_GE(u.x, 0.0f);
            ASSERT_LT(u.x, 1.0f);
            ASSERT_GE(u.y, 0.0f);
            ASSERT_LT(u.y, 1.0f);
            xs.insert(int(u.x * count));
            ys.insert(int(u.y * count));
        }
        EXPECT_EQ(int(ys.size()), count);
        // x is stratified into m * ceil(count / m) >= count fine strata: distinct for a square.
        if (count == 64 || count == 100) {
            EXPECT_EQ(int(xs.size()), count);
        }
    }
}

TEST(SamplingDirections, CosineWeightedMoments) {
    // For pdf cos(theta)/pi: E[cos theta] = 2/3, E[cos^2 theta] = 1/2, tangential means 0.
    const vec3 normals[] = {vec3(0, 0, 1), vec3(0, 0, -1), normalize(vec3(1, -2, 0.5f))};
    for (vec3 n : normals) {
        vec3 t1, t2;
        orthonormalBasis(n, t1, t2);
        EXPECT_NEAR(dot(t1, n), 0.0f, 1e-6f);
        EXPECT_NEAR(dot(t2, n), 0.0f, 1e-6f);
        EXPECT_NEAR(dot(t1, t2), 0.0f, 1e-6f);
        const int count = 4096;
        double cos1 = 0.0, cos2 = 0.0, tangential = 0.0;
        for (int s = 0; s < count; ++s) {
            vec3 d = cosineDirection(n, correlatedMultiJitter(s, count, 3u));
            ASSERT_NEAR(length(d), 1.0f, 1e-5f);
            ASSERT_GE(dot(d, n), 0.0f);
            cos1 += dot(d, n);
            cos2 += dot(d, n) * dot(d, n);
            tangential += dot(d, t1) + dot(d, t2);
        }
        EXPECT_NEAR(cos1 / count, 2.0 / 3.0, 1e-3);
        EXPECT_NEAR(cos2 / count, 0.5, 1e-3);
        EXPECT_NEAR(tangential / count, 0.0, 2e-3);
    }
}

TEST(SamplingDirections, StochasticRaysEstimateHowellC11) {
    // Rays from the floor square (two triangles) hitting the parallel unit ceiling at z = 1
    // estimate Howell C-11, 0.199824895698 (binomial sd with 2 x 16384 rays: < 0.0023).
    const PatchGeometry floor[2] = {makePatchGeometry({0, 0, 0}, {1, 0, 0}, {1, 1, 0}),
                                    makePatchGeometry({0, 0, 0}, {1, 1, 0}, {0, 1, 0})};
    const int count = 16384;
    double hits = 0.0;
    for (int t = 0; t < 2; ++t) {
        uint seed = patchSeed(uint(t), 2024u);
        for (int k = 0; k < count; ++k) {
            vec3 origin, direction;
            stochasticRay(seed, k, count, floor[t], origin, direction);
            if (direction.z <= 0.0f) continue;  // grazing: misses the ceiling
            float s = (1.0f - origin.z) / direction.z;
            vec3 x = origin + direction * s;
            if (x.x >= 0 && x.x <= 1 && x.y >= 0 && x.y <= 1) hits += 0.5;  // area weight 1/2
        }
    }
    EXPECT_NEAR(hits / count, verify::kHowellC11, 0.006);
}

}  // namespace
}  // namespace daisy::shared
