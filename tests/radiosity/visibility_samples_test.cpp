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
