// Shaft culling geometry (Haines & Wallace 1994): the hull of two polygons and what it excludes.
// Oracles are configurations whose answer is evident by construction.
#include "radiosity/shaft.h"

#include <gtest/gtest.h>

#include "radiosity/patch_clusters.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

// Unit squares at z = 0 and z = 1: the shaft is the unit cube.
struct CubeShaft : ::testing::Test {
    void SetUp() override {
        const Vec3d p[] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
        const Vec3d q[] = {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}};
        ASSERT_TRUE(shaft.build(p, q, 1e-9));
    }
    static ShaftPolygon triangle(Vec3d a, Vec3d b, Vec3d c) {
        const Vec3d points[] = {a, b, c};
        return ShaftPolygon(points, normalize(cross(b - a, c - a)));
    }
    Shaft shaft;
};

TEST_F(CubeShaft, HasTheSixFacesOfTheCube) {
    EXPECT_EQ(shaft.planeCount(), 6);
}

TEST_F(CubeShaft, ExcludesWhatLiesOutsideOrOnlyTouches) {
    EXPECT_FALSE(
        shaft.excludesPolygon(triangle({0.2, 0.2, 0.5}, {0.8, 0.2, 0.5}, {0.5, 0.8, 0.5})));
    EXPECT_TRUE(shaft.excludesPolygon(triangle({2, 0, 0.5}, {3, 0, 0.5}, {2, 1, 0.5})));
    // A neighbour sharing the edge x = 0 of the bottom square, in its plane.
    EXPECT_TRUE(shaft.excludesPolygon(triangle({-1, 0, 0}, {0, 0, 0}, {0, 1, 0})));
    // A wall standing on that edge: it touches the shaft's side face only.
    EXPECT_TRUE(shaft.excludesPolygon(triangle({0, 0, 0}, {0, 1, 0}, {0, 0, 1})));
    // A triangle cutting through a corner of the cube from outside.
    EXPECT_FALSE(
        shaft.excludesPolygon(triangle({-0.5, 0.5, 0.5}, {0.5, -0.5, 0.5}, {-0.5, -0.5, 0.9})));
    Bounds3d box;
    box.extend({0.4, 0.4, 0.4});
    box.extend({0.6, 0.6, 0.6});
    EXPECT_FALSE(shaft.excludesBox(box));
    box = {};
    box.extend({1.5, 0, 0});
    box.extend({2, 1, 1});
    EXPECT_TRUE(shaft.excludesBox(box));
}

TEST(Shaft, CoplanarPolygonsHaveNoShaft) {
    const Vec3d p[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const Vec3d q[] = {{2, 0, 0}, {3, 0, 0}, {2, 1, 0}};
    Shaft shaft;
    EXPECT_FALSE(shaft.build(p, q, 1e-9));
    EXPECT_FALSE(shaft.excludesBox(Bounds3d{}));  // an invalid shaft culls nothing
}

TEST(Shaft, SkewShaftOfTwoTriangles) {
    // A floor triangle and a wall triangle sharing no edge; the midpoint of a segment between
    // them lies inside, a point beyond the wall does not.
    const Vec3d p[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const Vec3d q[] = {{2, 0, 1}, {2, 1, 1}, {2, 0, 2}};
    Shaft shaft;
    ASSERT_TRUE(shaft.build(p, q, 1e-9));
    const auto tiny = [](Vec3d c) {
        const Vec3d points[] = {c, c + Vec3d{0.01, 0, 0}, c + Vec3d{0, 0.01, 0}};
        return ShaftPolygon(points, {0, 0, 1});
    };
    EXPECT_FALSE(shaft.excludesPolygon(tiny({1.0, 0.3, 0.6})));
    EXPECT_TRUE(shaft.excludesPolygon(tiny({3.0, 0.3, 1.2})));
}

// A solid face between two squares covers their shaft only when it spans every segment.
TEST(PatchClusters, SolidFaceCoversAShaftItCrossesEntirely) {
    TriangleMesh mesh;
    verify::addGrid(mesh, {-1, -1, 0.5}, {3, 0, 0}, {0, 3, 0}, 3, 3);  // 9 quads tiling a square
    const PatchMesh patches = verify::patchesOf(mesh);
    const PatchClusters clusters = buildPatchClusters(patches, 1e-9);
    ASSERT_EQ(clusters.faces.size(), 1u);
    ASSERT_EQ(clusters.blockers.size(), 1u);  // the face stands in for its 18 triangles
    EXPECT_EQ(clusters.faces[0].outline.size(), 4u);
    const Vec3d p[] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const Vec3d q[] = {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}};
    const Vec3d far[] = {{5, 0, 1}, {5, 1, 1}, {6, 1, 1}, {6, 0, 1}};
    EXPECT_TRUE(faceCoversShaft(clusters.faces[0], p, q, 1e-6));
    EXPECT_FALSE(faceCoversShaft(clusters.faces[0], p, far, 1e-6));
}

TEST(PatchClusters, RunsOfCoplanarPatchesUpToTheSizeLimit) {
    TriangleMesh mesh;
    verify::addGrid(mesh, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 5, 5);  // 50 coplanar triangles
    verify::addGrid(mesh, {0, 0, 1}, {0, 1, 0}, {1, 0, 0}, 1, 1);  // 2 in another plane
    const PatchClusters clusters = buildPatchClusters(verify::patchesOf(mesh), 1e-9, 32);
    ASSERT_EQ(clusters.clusterCount(), 3u);
    EXPECT_EQ(clusters.cluster(0).begin, 0u);
    EXPECT_EQ(clusters.cluster(0).end, 32u);
    EXPECT_EQ(clusters.cluster(1).end, 50u);
    EXPECT_EQ(clusters.cluster(2).end, 52u);
    // Every node's children split its range in two.
    for (const ClusterNode& node : clusters.nodes) {
        if (node.firstChild == 0) {
            EXPECT_EQ(node.end - node.begin, 1u);
            continue;
        }
        EXPECT_EQ(clusters.nodes[node.firstChild].begin, node.begin);
        EXPECT_EQ(clusters.nodes[node.firstChild + 1].end, node.end);
    }
}

}  // namespace
}  // namespace daisy
