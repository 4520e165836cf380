// The flat BVH (raycast/flat_bvh.h) and its shared traversal (shared/bvh_traverse.h). Oracles:
// the structural invariants (validateFlatBvh), and brute force: the closest hit and any-hit
// answers of a loop over every triangle with the same watertight test (shared/intersect.h).
#include "raycast/flat_bvh.h"

#include <gtest/gtest.h>

#include <random>

#include "geometry/bounds.h"
#include "scene/load_scene.h"
#include "shared/bvh_traverse.h"
#include "test_util.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

using shared::vec3;

PatchMesh cornellBox(double maxEdge) {
    auto scene = loadScene(test::assetPath("scenes/cornell_box.gltf"));
    EXPECT_TRUE(scene.ok());
    return std::move(buildPatchMesh(scene->mesh, maxEdge).value());
}

// The closest hit over every triangle: same test, nearest t, the lowest index on a tie.
shared::BvhHit bruteClosest(const FlatBvh& bvh, vec3 org, vec3 dir, float tmin, float tmax) {
    shared::BvhHit hit{tmax, DAISY_NO_HIT, DAISY_NO_HIT};
    const shared::WatertightRay ray = shared::makeWatertightRay(org, dir);
    for (uint32_t k = 0; k < bvh.triangles.size(); ++k) {
        const shared::BvhTriangle& t = bvh.triangles[k];
        float th = 0.0f;
        if (shared::intersectTriangle(ray, t.a, t.b, t.c, tmin, hit.t, th)) {
            hit = {th, k, t.patchIndex};
        }
    }
    return hit;
}

TEST(FlatBvh, ValidOnSmallAndLargeMeshes) {
    for (int n : {1, 2, 5}) {
        const PatchMesh cube = verify::patchesOf(verify::unitCubeRoom(n));
        auto bvh = buildFlatBvh(cube);
        ASSERT_TRUE(bvh.ok()) << bvh.error().message;
        EXPECT_EQ(validateFlatBvh(*bvh, cube), "") << n;
    }
    TriangleMesh one;
    verify::addGrid(one, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 1, 1);
    one.triangles.pop_back();
    one.materials.pop_back();
    const PatchMesh single = verify::patchesOf(one);
    auto bvh = buildFlatBvh(single);
    ASSERT_TRUE(bvh.ok());
    EXPECT_EQ(bvh->nodes.size(), 1u);  // one leaf
    EXPECT_EQ(validateFlatBvh(*bvh, single), "");
    auto empty = buildFlatBvh(PatchMesh{});
    ASSERT_TRUE(empty.ok());
    EXPECT_TRUE(empty->nodes.empty());

    const PatchMesh cornell = cornellBox(0.05);
    auto big = buildFlatBvh(cornell);
    ASSERT_TRUE(big.ok()) << big.error().message;
    EXPECT_EQ(validateFlatBvh(*big, cornell), "");
    EXPECT_GT(cornell.patchCount(), 1000u);
    EXPECT_LE(big->depth, DAISY_BVH_STACK_SIZE);
}

// validateFlatBvh catches what it promises to catch.
TEST(FlatBvh, ValidationRejectsBrokenTrees) {
    const PatchMesh cube = verify::patchesOf(verify::unitCubeRoom(2));
    const FlatBvh good = std::move(buildFlatBvh(cube).value());
    FlatBvh bad = good;
    bad.triangles[3] = bad.triangles[4];
    EXPECT_NE(validateFlatBvh(bad, cube), "");
    bad = good;
    bad.nodes[1].hi.x += 10.0f;  // a child sticking out of the root
    EXPECT_NE(validateFlatBvh(bad, cube), "");
    bad = good;
    bad.triangles[0].a.x += 1e-3f;
    EXPECT_NE(validateFlatBvh(bad, cube), "");
}

// Random rays through the subdivided Cornell box (about 4k triangles): the traversal's closest
// hit and any-hit answers equal brute force's exactly.
TEST(FlatBvh, TraversalMatchesBruteForce) {
    const PatchMesh mesh = cornellBox(0.05);
    const FlatBvh bvh = std::move(buildFlatBvh(mesh).value());
    const shared::BvhNodeBuffer nodes{bvh.nodes.data()};
    const shared::BvhTriangleBuffer triangles{bvh.triangles.data()};
    Bounds3d bounds;
    for (const Vec3d& p : mesh.positions)
        bounds.extend(p);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const auto inBox = [&]() {
        const Vec3d e = bounds.extent();
        return vec3(float(bounds.lo.x + e.x * unit(rng)), float(bounds.lo.y + e.y * unit(rng)),
                    float(bounds.lo.z + e.z * unit(rng)));
    };
    int hits = 0;
    int blocked = 0;
    for (int k = 0; k < 3000; ++k) {
        const vec3 org = inBox();
        // Every third segment ends on a patch's centroid: rays at and through the geometry.
        const Vec3d& c = mesh.centroids[std::size_t(unit(rng) * double(mesh.patchCount() - 1))];
        const vec3 end = k % 3 == 0 ? vec3(float(c.x), float(c.y), float(c.z)) : inBox();
        const vec3 dir = end - org;
        if (length(dir) == 0.0f) continue;
        const shared::BvhHit expected = bruteClosest(bvh, org, dir, 0.0f, 1e30f);
        const shared::BvhHit actual =
            shared::bvhClosestHit(org, dir, 0.0f, 1e30f, nodes, triangles);
        ASSERT_EQ(actual.triangle == DAISY_NO_HIT, expected.triangle == DAISY_NO_HIT) << k;
        if (expected.triangle != DAISY_NO_HIT) {
            ++hits;
            // Equal t at a shared edge may name either triangle; t itself must agree.
            EXPECT_EQ(actual.t, expected.t) << k;
        }
        // The segment org -> end (t in (margin, 1 - margin)) as a shadow ray.
        const bool expectBlocked =
            bruteClosest(bvh, org, dir, DAISY_SEGMENT_MARGIN, 1.0f - DAISY_SEGMENT_MARGIN)
                .triangle != DAISY_NO_HIT;
        EXPECT_EQ(shared::bvhOccluded(org, dir, DAISY_SEGMENT_MARGIN, 1.0f - DAISY_SEGMENT_MARGIN,
                                      nodes, triangles),
                  expectBlocked)
            << k;
        blocked += expectBlocked ? 1 : 0;
    }
    // Both answers occur often enough to mean something.
    EXPECT_GT(hits, 2000);
    EXPECT_GT(blocked, 300);
    EXPECT_LT(blocked, 2900);
}

}  // namespace
}  // namespace daisy
