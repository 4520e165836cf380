// The ray caster (raycast/ray_caster.h) through its factory. Oracles: segments and rays whose
// occlusion, first hit and hit point are evident by construction.
#include "raycast/ray_caster.h"

#include <gtest/gtest.h>

#include <cmath>

#include "verify/scenes.h"

namespace daisy {
namespace {

// A unit square at z = 1 (two triangles): segments through it are blocked, beside it not,
// ending on it not (the end point's own patch is excluded), empty never.
TEST(RayCaster, OcclusionInEveryPacketMode) {
    TriangleMesh mesh;
    verify::addGrid(mesh, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, 1, 1);
    const PatchMesh patches = verify::patchesOf(mesh);
    auto caster = makeRayCaster(patches);
    ASSERT_TRUE(caster.ok()) << caster.error().message;
    SegmentArrays segments;
    segments.resize(39);
    std::vector<uint8_t> expected;
    for (int k = 0; k < 37; ++k) {  // more than two packets, a partial one at the end
        const float x = 0.05f + 0.025f * float(k);
        segments.set(k, x, 0.5f, 0, x, 0.5f, 2);
        expected.push_back(x < 1.0f ? 1 : 0);
    }
    segments.set(37, 0.5f, 0.5f, 0, 0.5f, 0.5f, 1);  // ends on the square
    expected.push_back(0);
    segments.set(38, 0.5f, 0.5f, 0, 0.5f, 0.5f, 0);  // empty
    expected.push_back(0);
    for (PacketMode mode : {PacketMode::Single, PacketMode::Packet4, PacketMode::Packet8,
                            PacketMode::Packet16, PacketMode::Stream}) {
        (*caster)->setPacketMode(mode);
        std::vector<uint8_t> blocked(segments.size(), 7);
        (*caster)->occluded(segments, blocked);
        EXPECT_EQ(blocked, expected) << packetModeName(mode);
    }
}

TEST(RayCaster, ClosestHitReportsThePatch) {
    TriangleMesh mesh;
    verify::addGrid(mesh, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, 1, 1);
    verify::addGrid(mesh, {0, 0, 2}, {1, 0, 0}, {0, 1, 0}, 1, 1);
    auto caster = makeRayCaster(verify::patchesOf(mesh));
    ASSERT_TRUE(caster.ok());
    const Ray rays[] = {
        {{0.7f, 0.2f, 0}, {0, 0, 1}}, {{0.2f, 0.7f, 0}, {0, 0, 1}}, {{0.5f, 0.5f, 0}, {0, 0, -1}}};
    uint32_t hits[3];
    (*caster)->closestHits(rays, hits);
    EXPECT_EQ(hits[0], 0u);  // (0.7, 0.2) is in the first triangle of the nearer square
    EXPECT_EQ(hits[1], 1u);
    EXPECT_EQ(hits[2], kNoPatch);
}

// Two unit squares at z = 1 and z = 2, robust and not: the hit point rebuilt from the patch's
// corners and the barycentrics is the ray's point at t (the plane z = 1 at t = 1), tNear skips
// the nearer square, and a miss reports kNoPatch at infinity.
TEST(RayCaster, SurfaceHitsCarryTheirPointOnThePatch) {
    TriangleMesh mesh;
    verify::addGrid(mesh, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, 1, 1);
    verify::addGrid(mesh, {0, 0, 2}, {1, 0, 0}, {0, 1, 0}, 1, 1);
    const PatchMesh patches = verify::patchesOf(mesh);
    for (bool robust : {false, true}) {
        auto caster = makeRayCaster(patches, {.robust = robust});
        ASSERT_TRUE(caster.ok()) << caster.error().message;
        const Ray rays[] = {{{0.7f, 0.2f, 0}, {0, 0, 1}},
                            {{0.2f, 0.7f, 0}, {0, 0, 1}},
                            {{0.5f, 0.5f, 0}, {0, 0, -1}}};
        SurfaceHit hits[3];
        (*caster)->closestSurfaceHits(rays, hits);
        for (int k = 0; k < 2; ++k) {
            ASSERT_LT(hits[k].patch, 2u) << "ray " << k;
            EXPECT_NEAR(hits[k].t, 1.0f, 1e-6f);
            const auto& corners = patches.patches[hits[k].patch];
            const double u = hits[k].u, v = hits[k].v;
            const Vec3d point = patches.positions[corners[0]] * (1 - u - v) +
                patches.positions[corners[1]] * u + patches.positions[corners[2]] * v;
            EXPECT_NEAR(point.x, rays[k].origin[0], 1e-6);
            EXPECT_NEAR(point.y, rays[k].origin[1], 1e-6);
            EXPECT_NEAR(point.z, 1.0, 1e-6);
        }
        EXPECT_EQ(hits[2].patch, kNoPatch);
        EXPECT_TRUE(std::isinf(hits[2].t));

        (*caster)->closestSurfaceHits(std::span<const Ray>(rays, 1), std::span<SurfaceHit>(hits, 1),
                                      /*tNear=*/1.5f);
        EXPECT_GE(hits[0].patch, 2u);
        EXPECT_LT(hits[0].patch, 4u);
        EXPECT_NEAR(hits[0].t, 2.0f, 1e-6f);
    }
}

}  // namespace
}  // namespace daisy
