// The cpu backend's vectorised hybrid kernel (radiosity/hybrid_far_field.h) against its oracle,
// the shared kernel (shared/formfactor.h) that the reference, vulkan and cuda backends run: the
// same operations in the same order, so every factor must be bit-identical, for far pairs (the
// vectorised lanes), near pairs (their refinement's points in lanes too, hybrid_near_cells.h)
// and clipped points (the fallback) alike.
#include "radiosity/hybrid_far_field.h"
#include "radiosity/hybrid_near_cells.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "shared/formfactor.h"

namespace daisy {
namespace {

using shared::PatchGeometry;
using shared::vec3;

// A random triangle of about `size` around `centre`, random orientation.
PatchGeometry randomTriangle(std::mt19937& rng, vec3 centre, float size) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const auto corner = [&]() { return centre + vec3(u(rng), u(rng), u(rng)) * size; };
    return shared::makePatchGeometry(corner(), corner(), corner());
}

// Pairs at distances from touching to 1000 sizes, in a box far from the origin too (the plane
// tolerances grow with the coordinates), at the levels the fast path takes (L <= 2) and one it
// leaves to the shared kernel (L = 3).
TEST(HybridFarField, BitIdenticalToTheSharedKernel) {
    std::mt19937 rng(1812);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::uniform_real_distribution<float> logDistance(-1.0f, 3.0f);
    int nonzero = 0, compared = 0;
    for (int k = 0; k < 20000; ++k) {
        const vec3 origin = k % 4 == 3 ? vec3(1000.0f, -250.0f, 40.0f) : vec3(0.0f);
        const float size = 0.05f + 0.2f * (u(rng) + 1.0f);
        const PatchGeometry i = randomTriangle(rng, origin, size);
        const float distance = size * std::pow(10.0f, logDistance(rng));
        const vec3 direction = shared::normalize(vec3(u(rng), u(rng), u(rng)) + vec3(0, 0, 1e-3f));
        const PatchGeometry j = randomTriangle(rng, origin + direction * distance, size);
        if (!(i.area > 1e-6f && j.area > 1e-6f)) continue;
        for (int level : {0, 1, 2, 3}) {
            const shared::PairFactors want = shared::pairFactors(DAISY_METHOD_HYBRID, level, i, j);
            const shared::PairFactors got = pairFactorsCpu(DAISY_METHOD_HYBRID, level, i, j);
            ASSERT_EQ(got.fij, want.fij) << "pair " << k << " level " << level;
            ASSERT_EQ(got.fji, want.fji) << "pair " << k << " level " << level;
            if (!shared::facingAway(i, j)) {  // a candidate: the evaluator's entry point
                const shared::PairFactors candidate =
                    candidatePairFactorsCpu(DAISY_METHOD_HYBRID, level, i, j);
                ASSERT_EQ(candidate.fij, want.fij) << "pair " << k << " level " << level;
                ASSERT_EQ(candidate.fji, want.fji) << "pair " << k << " level " << level;
            }
            ++compared;
            nonzero += want.fij > 0.0f ? 1 : 0;
        }
    }
    // Most pairs face each other and most are far: the vectorised lanes did real work.
    EXPECT_GT(compared, 70000);
    EXPECT_GT(nonzero, compared / 8);
}

// The evaluator's batch entry point: the far cells of many pairs share SIMD groups, so each
// lane holds another pair's point. Every candidate pair of the random set above, at L = 0..2,
// in one batch: each factor bit-identical to the shared kernel's (clamped at 0).
TEST(HybridFarField, BatchOfPairsIsBitIdenticalToTheSharedKernel) {
    std::mt19937 rng(2024);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::uniform_real_distribution<float> logDistance(-1.0f, 3.0f);
    std::vector<PatchGeometry> geometry;
    std::vector<shared::PairIndex> pairs;
    while (pairs.size() < 6000) {
        const float size = 0.05f + 0.2f * (u(rng) + 1.0f);
        const PatchGeometry i = randomTriangle(rng, vec3(0.0f), size);
        const float distance = size * std::pow(10.0f, logDistance(rng));
        const vec3 direction = shared::normalize(vec3(u(rng), u(rng), u(rng)) + vec3(0, 0, 1e-3f));
        const PatchGeometry j = randomTriangle(rng, direction * distance, size);
        if (!(i.area > 1e-6f && j.area > 1e-6f) || shared::facingAway(i, j)) continue;
        geometry.push_back(i);
        geometry.push_back(j);
        const uint32_t first = uint32_t(geometry.size() - 2);
        pairs.push_back({first, first + 1});
    }
    FarFieldScratch scratch;
    for (int level : {0, 1, 2}) {
        std::vector<shared::PairFactors> got(pairs.size(), shared::PairFactors{-1.0f, -1.0f});
        candidateFactorsCpu(DAISY_METHOD_HYBRID, level, geometry, farFieldPatches(geometry), pairs,
                            got, scratch);
        int positive = 0;
        for (std::size_t k = 0; k < pairs.size(); ++k) {
            const shared::PairFactors exact = shared::pairFactors(
                DAISY_METHOD_HYBRID, level, geometry[pairs[k].i], geometry[pairs[k].j]);
            const float want = std::max(0.0f, exact.fij);
            ASSERT_EQ(got[k].fij, want) << "pair " << k << " level " << level;
            ASSERT_EQ(got[k].fji, std::max(0.0f, exact.fji)) << "pair " << k << " level " << level;
            positive += want > 0.0f ? 1 : 0;
        }
        EXPECT_GT(positive, int(pairs.size()) / 4) << level;
    }
}

// A root triangle DAISY_FF_MID_RATIO of its own diameter from j is one cell: a small patch
// facing a far one takes the same value at every level (its cells are never split), and that
// value is the closed form of a differential area to a parallel coaxial square (Howell's
// catalogue B-3) within the middle rule's error band.
TEST(HybridFarField, FarRootIsOneCellAtEveryLevel) {
    const float h = 2.0f;  // distance of the square (side 1, two triangles) above i
    const PatchGeometry i = shared::makePatchGeometry(vec3(-0.05f, -0.05f, 0.0f),
                                                      vec3(0.05f, -0.05f, 0.0f), vec3(0, 0.05f, 0));
    const PatchGeometry j0 =
        shared::makePatchGeometry(vec3(-0.5f, -0.5f, h), vec3(0.5f, 0.5f, h), vec3(0.5f, -0.5f, h));
    const PatchGeometry j1 =
        shared::makePatchGeometry(vec3(-0.5f, -0.5f, h), vec3(-0.5f, 0.5f, h), vec3(0.5f, 0.5f, h));
    const float f1 = pairFactorsCpu(DAISY_METHOD_HYBRID, 1, i, j0).fij +
        pairFactorsCpu(DAISY_METHOD_HYBRID, 1, i, j1).fij;
    for (int level : {0, 2, 3}) {
        const float f = pairFactorsCpu(DAISY_METHOD_HYBRID, level, i, j0).fij +
            pairFactorsCpu(DAISY_METHOD_HYBRID, level, i, j1).fij;
        EXPECT_EQ(f, f1) << level;
    }
    // Howell B-3 at the square's centre: F = (2/pi) [a/sqrt(1+a^2) atan(b/sqrt(1+a^2)) + (same
    // with a, b swapped)], a = b = half side / h.
    const double a = 0.5 / h;
    const double s = std::sqrt(1.0 + a * a);
    const double centre = 4.0 / (2.0 * M_PI) * (2.0 * a / s * std::atan(a / s));
    // i's centroid is 1/60 off the axis: the factor there differs from the centre's by ~1e-5.
    EXPECT_NEAR(f1, centre, 2e-4 * centre);
}

// Pairs with near cells, whose points the rule of hybrid_near_cells.h evaluates in lanes a
// refinement step at a time: triangles sharing an edge or a corner at random fold angles, and
// ones a hair apart, at levels 0..3 and at F's tolerance and the hierarchical transport's looser
// one (more and fewer splits): bit-identical to the shared kernel, which refined most of them.
TEST(HybridFarField, NearCellsAreBitIdenticalToTheSharedKernel) {
    std::mt19937 rng(2026);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    int compared = 0, refined = 0;
    for (int k = 0; k < 3000; ++k) {
        const vec3 origin = k % 3 == 2 ? vec3(-300.0f, 80.0f, 1200.0f) : vec3(0.0f);
        const float size = 0.1f + 0.4f * (u(rng) + 1.0f);
        const PatchGeometry i = randomTriangle(rng, origin, size);
        const vec3 far = origin + vec3(u(rng), u(rng), u(rng)) * (2.0f * size);
        const vec3 gap = vec3(u(rng), u(rng), u(rng)) * (1e-3f * size);
        const PatchGeometry j = k % 3 == 0 ? shared::makePatchGeometry(i.b, i.a, far)
            : k % 3 == 1                   ? shared::makePatchGeometry(i.a, far, far + gap * 3e2f)
                                           : shared::makePatchGeometry(i.b + gap, i.a + gap, far);
        if (!(i.area > 1e-6f && j.area > 1e-6f) || shared::facingAway(i, j)) continue;
        for (int level : {0, 1, 2, 3}) {
            for (float tolerance : {DAISY_FF_REL_TOL, 1e-2f}) {
                const float want = shared::hybridPairFactorWithin(level, i, j, true, tolerance);
                FarFieldScratch scratch;
                const float got = hybridNearPairFactor(level, i, j, tolerance, scratch);
                ASSERT_EQ(got, want) << "pair " << k << " level " << level << " " << tolerance;
                ++compared;
                refined += shared::hybridPairFactorWithin(level, i, j, false, tolerance) ==
                    DAISY_FF_NEEDS_NEAR_CELLS;
            }
        }
    }
    EXPECT_GT(compared, 8000);
    EXPECT_GT(refined, compared / 2);
}

// Coplanar neighbours and a pair sharing an edge (the adaptive rule's cases) and the other
// methods: the shared kernel's own values.
TEST(HybridFarField, NearPairsAndOtherMethodsAreTheSharedKernel) {
    const PatchGeometry floor =
        shared::makePatchGeometry(vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0));
    const PatchGeometry wall =
        shared::makePatchGeometry(vec3(0, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1));
    const PatchGeometry ceiling =
        shared::makePatchGeometry(vec3(0, 0, 40), vec3(0, 1, 40), vec3(1, 0, 40));
    for (int method : {DAISY_METHOD_HYBRID, DAISY_METHOD_RIEMANN, DAISY_METHOD_NUSSELT}) {
        for (const PatchGeometry* other : {&wall, &ceiling}) {
            const shared::PairFactors want = shared::pairFactors(method, 1, floor, *other);
            const shared::PairFactors got = pairFactorsCpu(method, 1, floor, *other);
            EXPECT_EQ(got.fij, want.fij) << method;
            EXPECT_EQ(got.fji, want.fji) << method;
            EXPECT_GT(got.fij, 0.0f) << method;
        }
    }
}

}  // namespace
}  // namespace daisy
