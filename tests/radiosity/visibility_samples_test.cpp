// The driver's batched shadow-ray samples must be the shared sequence itself (DESIGN.md section
// 3: the same samples on every backend), so the oracle is shared::visibilitySamplePair, called
// once per sample: equality is bitwise.
#include "radiosity/visibility_samples.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "shared/rng.h"
#include "shared/sampling.h"
#include "shared/visibility.h"

namespace daisy {
namespace {

using shared::PatchGeometry;
using shared::vec3;

PatchGeometry randomTriangle(std::mt19937& rng) {
    std::uniform_real_distribution<float> coordinate(-3.0f, 3.0f);
    const auto point = [&] { return vec3(coordinate(rng), coordinate(rng), coordinate(rng)); };
    return shared::makePatchGeometry(point(), point(), point());
}

bool sameBits(const vec3& a, const vec3& b) {
    return std::memcmp(&a, &b, sizeof(vec3)) == 0;
}

TEST(VisibilitySamples, BitIdenticalToTheSharedSequence) {
    std::mt19937 rng(2024);
    for (int trial = 0; trial < 200; ++trial) {
        const PatchGeometry i = randomTriangle(rng);
        const PatchGeometry j = randomTriangle(rng);
        const uint32_t seed = shared::pairSeed(uint32_t(trial), uint32_t(trial * 7 + 3), 1u);
        for (int count : {1, 3, 4, 16, 17, 64, 300}) {
            std::vector<vec3> pi(count), pj(count);
            visibilitySamples(seed, count, i, j, pi.data(), pj.data());
            for (int k = 0; k < count; ++k) {
                vec3 expectedI, expectedJ;
                shared::visibilitySamplePair(seed, k, count, i, j, expectedI, expectedJ);
                ASSERT_TRUE(sameBits(pi[k], expectedI)) << "trial " << trial << " k " << k;
                ASSERT_TRUE(sameBits(pj[k], expectedJ)) << "trial " << trial << " k " << k;
            }
        }
    }
}

// The batched segments and their kernel weights are shared::shadowSegment's, bit for bit (the
// pair-kernel backends' V must equal the cpu backend's), and the weight is cos_i cos_j / r^2 of
// the untrimmed points (a double-precision oracle), 0 where a point is behind the other's plane.
TEST(VisibilitySamples, SegmentsAndKernelWeightsMatchTheSharedFunction) {
    std::mt19937 rng(77);
    int behind = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const PatchGeometry i = randomTriangle(rng);
        const PatchGeometry j = randomTriangle(rng);
        const uint32_t seed = shared::pairSeed(uint32_t(trial), 5u, 1u);
        const int count = 16;
        SegmentArrays segments;
        segments.resize(count);
        std::vector<float> weights(count);
        shadowSegments(seed, count, i, j, 1e-5f, segments, 0, weights.data());
        for (int k = 0; k < count; ++k) {
            vec3 origin, end;
            float weight = -1.0f;
            const bool kept =
                shared::shadowSegment(seed, k, count, i, j, 1e-5f, origin, end, weight);
            ASSERT_EQ(std::memcmp(&weight, &weights[std::size_t(k)], sizeof(float)), 0)
                << "trial " << trial << " k " << k;
            if (kept) {
                EXPECT_EQ(segments.x0[std::size_t(k)], origin.x);
                EXPECT_EQ(segments.z1[std::size_t(k)], end.z);
            }
            vec3 pi, pj;
            shared::visibilitySamplePair(seed, k, count, i, j, pi, pj);
            const double dx = double(pj.x) - pi.x, dy = double(pj.y) - pi.y,
                         dz = double(pj.z) - pi.z;
            const double r2 = dx * dx + dy * dy + dz * dz;
            const double cosI = (i.normal.x * dx + i.normal.y * dy + i.normal.z * dz) / r2;
            const double cosJ = -(j.normal.x * dx + j.normal.y * dy + j.normal.z * dz) / r2;
            const double expected = cosI > 0 && cosJ > 0 ? cosI * cosJ : 0.0;
            behind += expected == 0.0 ? 1 : 0;
            // Float dot products of a grazing segment cancel: their rounding is relative to
            // |d|, so the weight's error is bounded by a few float epsilons of 1 / r^2.
            EXPECT_NEAR(weight, expected, 1e-4 * expected + 1e-5 / r2)
                << "trial " << trial << " k " << k;
        }
    }
    EXPECT_GT(behind, 0);  // random triangles straddle each other's planes
}

TEST(VisibilitySamples, KernelWeightedVisibilityIsExactWhenAllAgree) {
    EXPECT_EQ(shared::kernelWeightedVisibility(3.0f, 3.0f, 4, 4), 1.0f);
    EXPECT_EQ(shared::kernelWeightedVisibility(0.0f, 3.0f, 0, 4), 0.0f);
    EXPECT_EQ(shared::kernelWeightedVisibility(1.0f, 4.0f, 2, 4), 0.25f);  // weights, not counts
    EXPECT_EQ(shared::kernelWeightedVisibility(0.0f, 0.0f, 1, 4), 0.25f);  // no usable weight
}

// Swapping the patches swaps the points (the shared contract), so F_ij and F_ji agree.
TEST(VisibilitySamples, SymmetricInThePair) {
    std::mt19937 rng(5);
    const PatchGeometry i = randomTriangle(rng);
    const PatchGeometry j = randomTriangle(rng);
    std::vector<vec3> a(16), b(16), c(16), d(16);
    visibilitySamples(99u, 16, i, j, a.data(), b.data());
    visibilitySamples(99u, 16, j, i, c.data(), d.data());
    for (int k = 0; k < 16; ++k) {
        EXPECT_TRUE(sameBits(a[k], d[k]));
        EXPECT_TRUE(sameBits(b[k], c[k]));
    }
}

}  // namespace
}  // namespace daisy
