// The shared ray tests (shared/intersect.h). Oracles: hits constructed by hand (a ray along an
// axis through a known point of an axis-aligned triangle), and watertightness (Woop, Benthin &
// Wald 2013, JCGT 2(1)): a ray through a closed fan of triangles around a vertex crosses the fan
// exactly once, wherever it goes through it, including exactly through a shared edge or the
// shared vertex.
#include "shared/intersect.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace daisy::shared {
namespace {

// Triangle (0,0,1), (1,0,1), (0,1,1): the z = 1 plane.
TEST(Intersect, KnownHitAndMisses) {
    const vec3 a(0, 0, 1), b(1, 0, 1), c(0, 1, 1);
    float t = -1.0f;
    WatertightRay ray = makeWatertightRay(vec3(0.25f, 0.25f, 0.0f), vec3(0, 0, 2));
    ASSERT_TRUE(intersectTriangle(ray, a, b, c, 0.0f, 1.0f, t));
    EXPECT_EQ(t, 0.5f);  // z = 0 + 2 t = 1
    EXPECT_FALSE(intersectTriangle(ray, a, b, c, 0.0f, 0.5f, t));  // tmax is exclusive
    EXPECT_FALSE(intersectTriangle(ray, a, b, c, 0.5f, 1.0f, t));  // so is tmin
    // From behind (both sides count) and an oblique ray.
    ray = makeWatertightRay(vec3(0.25f, 0.25f, 3.0f), vec3(0, 0, -1));
    ASSERT_TRUE(intersectTriangle(ray, a, b, c, 0.0f, 10.0f, t));
    EXPECT_FLOAT_EQ(t, 2.0f);
    ray = makeWatertightRay(vec3(-1.0f, -1.0f, -1.0f), vec3(1.2f, 1.2f, 2.0f));  // to (.2, .2, 1)
    ASSERT_TRUE(intersectTriangle(ray, a, b, c, 0.0f, 10.0f, t));
    EXPECT_FLOAT_EQ(t, 1.0f);
    // Outside the hypotenuse, and parallel to the plane.
    ray = makeWatertightRay(vec3(0.6f, 0.6f, 0.0f), vec3(0, 0, 1));
    EXPECT_FALSE(intersectTriangle(ray, a, b, c, 0.0f, 10.0f, t));
    ray = makeWatertightRay(vec3(0.1f, 0.1f, 1.0f), vec3(1, 0, 0));
    EXPECT_FALSE(intersectTriangle(ray, a, b, c, -10.0f, 10.0f, t));
}

// A fan of `sides` triangles around `centre` in the plane spanned by u, v, with the winding of
// the triangles alternating when `mixedWinding` (neighbours then traverse their shared edge in
// the same direction, the harder case for a tie-break).
struct Fan {
    std::vector<vec3> a, b, c;
};

Fan makeFan(vec3 centre, vec3 u, vec3 v, int sides, bool mixedWinding) {
    Fan fan;
    for (int k = 0; k < sides; ++k) {
        const float p0 = 2.0f * DAISY_PI * float(k) / float(sides);
        const float p1 = 2.0f * DAISY_PI * float(k + 1) / float(sides);
        const vec3 r0 = centre + u * std::cos(p0) + v * std::sin(p0);
        const vec3 r1 = k + 1 == sides ? centre + u : centre + u * std::cos(p1) + v * std::sin(p1);
        fan.a.push_back(centre);
        const bool flip = mixedWinding && k % 2 == 1;
        fan.b.push_back(flip ? r1 : r0);
        fan.c.push_back(flip ? r0 : r1);
    }
    return fan;
}

int hitCount(const Fan& fan, vec3 org, vec3 dir) {
    const WatertightRay ray = makeWatertightRay(org, dir);
    int hits = 0;
    for (std::size_t k = 0; k < fan.a.size(); ++k) {
        float t = 0.0f;
        hits += intersectTriangle(ray, fan.a[k], fan.b[k], fan.c[k], 0.0f, 100.0f, t) ? 1 : 0;
    }
    return hits;
}

TEST(Intersect, RaysThroughTheSharedVertexHitExactlyOnce) {
    for (bool mixed : {false, true}) {
        // Axis-aligned fan: rays along z through the vertex see it at exactly (0, 0).
        const Fan flat = makeFan(vec3(0.3f, -0.7f, 2.0f), vec3(1, 0, 0), vec3(0, 1, 0), 7, mixed);
        EXPECT_EQ(hitCount(flat, vec3(0.3f, -0.7f, 0.0f), vec3(0, 0, 1)), 1) << mixed;
        EXPECT_EQ(hitCount(flat, vec3(0.3f, -0.7f, 5.0f), vec3(0, 0, -3)), 1) << mixed;
        // Oblique rays through the vertex of a tilted fan, from many directions.
        const vec3 centre(0.1f, 0.2f, 0.3f);
        const Fan tilted = makeFan(centre, normalize(vec3(1, 0.2f, 0.1f)),
                                   normalize(vec3(-0.1f, 1, 0.4f)), 6, mixed);
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
        for (int k = 0; k < 200; ++k) {
            const vec3 dir(unit(rng), unit(rng), unit(rng));
            const vec3 n = cross(tilted.b[0] - centre, tilted.c[0] - centre);
            if (std::abs(dot(normalize(dir), normalize(n))) < 0.05f) continue;  // too grazing
            EXPECT_EQ(hitCount(tilted, centre - dir * 2.0f, dir), 1) << k << " mixed " << mixed;
        }
    }
}

TEST(Intersect, RaysThroughSharedEdgesHitExactlyOnce) {
    for (bool mixed : {false, true}) {
        const Fan fan = makeFan(vec3(0, 0, 0), normalize(vec3(1, 0.3f, -0.2f)),
                                normalize(vec3(-0.3f, 1, 0.5f)), 8, mixed);
        std::mt19937 rng(11);
        std::uniform_real_distribution<float> unit(0.0f, 1.0f);
        std::uniform_real_distribution<float> signedUnit(-1.0f, 1.0f);
        const vec3 n = normalize(cross(fan.b[0] - fan.a[0], fan.c[0] - fan.a[0]));
        int tested = 0;
        for (int k = 0; k < 4000; ++k) {
            // A point on spoke s (the edge shared by triangles s - 1 and s), in float.
            const int s = int(unit(rng) * 8.0f) % 8;
            const vec3 spoke = mixed && s % 2 == 1 ? fan.c[s] : fan.b[s];
            const vec3 target = fan.a[0] + (spoke - fan.a[0]) * (0.05f + 0.9f * unit(rng));
            vec3 dir(signedUnit(rng), signedUnit(rng), signedUnit(rng));
            if (std::abs(dot(normalize(dir), n)) < 0.05f) continue;
            EXPECT_EQ(hitCount(fan, target - dir * 3.0f, dir), 1) << k;
            ++tested;
        }
        EXPECT_GT(tested, 3000);
    }
}

// Axis-aligned rays exactly through grid lines of a triangulated square: every edge value is an
// exact zero somewhere, so only the tie-break decides. Each ray must hit the square once.
TEST(Intersect, ExactZerosOnAGridAreCountedOnce) {
    std::vector<vec3> a, b, c;
    const int n = 4;
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            const vec3 p00(float(x), float(y), 1), p10(float(x + 1), float(y), 1);
            const vec3 p01(float(x), float(y + 1), 1), p11(float(x + 1), float(y + 1), 1);
            a.push_back(p00), b.push_back(p10), c.push_back(p11);
            a.push_back(p00), b.push_back(p11), c.push_back(p01);
        }
    }
    for (int iy = 1; iy < 4 * n; ++iy) {
        for (int ix = 1; ix < 4 * n; ++ix) {
            const vec3 org(float(ix) * 0.25f, float(iy) * 0.25f, 0.0f);
            for (float dz : {1.0f, -1.0f}) {
                const WatertightRay ray =
                    makeWatertightRay(dz > 0 ? org : org + vec3(0, 0, 2), vec3(0, 0, dz));
                int hits = 0;
                for (std::size_t k = 0; k < a.size(); ++k) {
                    float t = 0.0f;
                    hits += intersectTriangle(ray, a[k], b[k], c[k], 0.0f, 10.0f, t) ? 1 : 0;
                }
                EXPECT_EQ(hits, 1) << org.x << ", " << org.y << " dz " << dz;
            }
        }
    }
}

TEST(Intersect, SlabTest) {
    const vec3 lo(0, 0, 0), hi(1, 2, 3);
    float entry = 0.0f;
    EXPECT_TRUE(
        intersectBox(vec3(-1, 1, 1), safeReciprocal(vec3(1, 0, 0)), lo, hi, 0.0f, 10.0f, entry));
    EXPECT_EQ(entry, 1.0f);
    EXPECT_FALSE(intersectBox(vec3(-1, 1, 1), safeReciprocal(vec3(1, 0, 0)), lo, hi, 0.0f, 0.5f,
                              entry));  // ends before the box
    EXPECT_FALSE(intersectBox(vec3(-1, 3, 1), safeReciprocal(vec3(1, 0, 0)), lo, hi, 0.0f, 10.0f,
                              entry));  // passes beside it
    // Origin on a slab plane with a zero direction component: no NaN, a hit.
    EXPECT_TRUE(
        intersectBox(vec3(0, 1, -1), safeReciprocal(vec3(0, 0, 1)), lo, hi, 0.0f, 10.0f, entry));
    // A flat box (a leaf of coplanar triangles) is still hit.
    EXPECT_TRUE(intersectBox(vec3(0.5f, 0.5f, -1), safeReciprocal(vec3(0, 0, 1)), vec3(0, 0, 1),
                             vec3(1, 1, 1), 0.0f, 10.0f, entry));
    EXPECT_EQ(entry, 2.0f);
}

}  // namespace
}  // namespace daisy::shared
