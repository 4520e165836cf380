// Shaft culling geometry (Haines & Wallace 1994): the hull of two polygons and what it excludes.
// Oracles are configurations whose answer is evident by construction.
#include "radiosity/shaft.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

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

// A convex polygon of n corners on a circle of radius r about c in the plane spanned by the unit
// vectors u and v, at jittered angles (corners in order, none collinear).
std::vector<Vec3d> randomPolygon(std::mt19937& rng, int n, Vec3d c, Vec3d u, Vec3d v, double r) {
    std::uniform_real_distribution<double> jitter(0.1, 0.9);
    std::vector<Vec3d> corners;
    for (int k = 0; k < n; ++k) {
        const double angle = 2 * M_PI * (k + jitter(rng)) / n;
        corners.push_back(c + u * (r * std::cos(angle)) + v * (r * std::sin(angle)));
    }
    return corners;
}

// The shaft against the textbook hull: every plane through three of the points with all points
// on one side is a facet of conv(P u Q) (brute force, O(n^4)). Random polygon pairs of 3 to 8
// corners in random planes; at random points of the hull's box, a tiny triangle is excluded
// when the point is outside the hull by a margin (the shaft found every facet) and kept when it
// is inside by a margin (no plane cuts into the hull).
TEST(Shaft, ExcludesExactlyWhatTheBruteForceHullExcludes) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(-1, 1);
    std::uniform_int_distribution<int> corners(3, 8);
    const auto direction = [&] {
        Vec3d d;
        do {
            d = {unit(rng), unit(rng), unit(rng)};
        } while (length(d) < 0.2 || length(d) > 1);
        return normalize(d);
    };
    int outside = 0, inside = 0;
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<Vec3d> polygons[2];
        for (std::vector<Vec3d>& polygon : polygons) {
            const Vec3d n = direction();
            const Vec3d u = normalize(cross(n, direction()));
            const Vec3d centre{2 * unit(rng), 2 * unit(rng), 2 * unit(rng)};
            polygon =
                randomPolygon(rng, corners(rng), centre, u, cross(n, u), 0.6 + 0.4 * unit(rng));
        }
        Shaft shaft;
        if (!shaft.build(polygons[0], polygons[1], 1e-9)) continue;
        std::vector<Vec3d> points = polygons[0];
        points.insert(points.end(), polygons[1].begin(), polygons[1].end());
        struct Facet {
            Vec3d n;  // unit, outward
            double offset;
        };
        std::vector<Facet> facets;
        for (std::size_t a = 0; a < points.size(); ++a) {
            for (std::size_t b = a + 1; b < points.size(); ++b) {
                for (std::size_t c = b + 1; c < points.size(); ++c) {
                    const Vec3d n = cross(points[b] - points[a], points[c] - points[a]);
                    if (length(n) < 1e-9) continue;
                    const Vec3d unitN = normalize(n);
                    double lo = 0, hi = 0;
                    for (const Vec3d& x : points) {
                        lo = std::min(lo, dot(unitN, x - points[a]));
                        hi = std::max(hi, dot(unitN, x - points[a]));
                    }
                    if (hi <= 1e-9) facets.push_back({unitN, dot(unitN, points[a])});
                    if (lo >= -1e-9) facets.push_back({-unitN, -dot(unitN, points[a])});
                }
            }
        }
        Bounds3d box;
        for (const Vec3d& x : points)
            box.extend(x);
        std::uniform_real_distribution<double> s(0, 1);
        for (int k = 0; k < 100; ++k) {
            const Vec3d x{box.lo.x + s(rng) * (box.hi.x - box.lo.x),
                          box.lo.y + s(rng) * (box.hi.y - box.lo.y),
                          box.lo.z + s(rng) * (box.hi.z - box.lo.z)};
            double beyond = -1e300;  // distance outside the hull's nearest facet plane
            for (const Facet& f : facets)
                beyond = std::max(beyond, dot(f.n, x) - f.offset);
            const Vec3d tri[] = {x, x + Vec3d{1e-4, 0, 0}, x + Vec3d{0, 1e-4, 1e-4}};
            const ShaftPolygon tiny(tri, normalize(cross(tri[1] - tri[0], tri[2] - tri[0])));
            if (beyond > 1e-2) {
                ++outside;
                EXPECT_TRUE(shaft.excludesPolygon(tiny)) << "trial " << trial << ", " << beyond;
            } else if (beyond < -1e-2) {
                ++inside;
                EXPECT_FALSE(shaft.excludesPolygon(tiny)) << "trial " << trial << ", " << beyond;
            }
        }
    }
    EXPECT_GT(outside, 1000);
    EXPECT_GT(inside, 1000);
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

// A coplanar run listed in shuffled order (as a Blender export lists a wall) is cut into
// kMaxScatteredClusterSize pieces whose trees split in space: every node holds a set of the
// cluster's patches, the children partition it, and two levels down each node's outline covers
// at most about a quarter of the run's (an index-range tree's would each span the whole floor).
// The same run in mesh order keeps the index-range clusters.
TEST(PatchClusters, ShuffledRunsSplitInSpace) {
    TriangleMesh mesh;
    verify::addGrid(mesh, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 20, 20);  // 800 coplanar triangles
    const PatchClusters ordered = buildPatchClusters(verify::patchesOf(mesh), 1e-9);
    EXPECT_EQ(ordered.clusterCount(), 25u);  // 800 / 32
    std::mt19937 rng(11);
    std::shuffle(mesh.triangles.begin(), mesh.triangles.end(), rng);
    const PatchClusters clusters = buildPatchClusters(verify::patchesOf(mesh), 1e-9);
    ASSERT_EQ(clusters.clusterCount(), 4u);  // 3 x 256 + 32
    EXPECT_EQ(clusters.cluster(0).end, kMaxScatteredClusterSize);
    std::vector<uint32_t> sorted = clusters.order;
    std::sort(sorted.begin(), sorted.end());
    for (uint32_t p = 0; p < 800; ++p)
        ASSERT_EQ(sorted[p], p);  // a permutation
    for (uint32_t c = 0; c < clusters.clusterCount(); ++c) {  // within its own index range
        const ClusterNode& root = clusters.cluster(c);
        for (uint32_t p = root.begin; p < root.end; ++p) {
            EXPECT_GE(clusters.order[p], root.begin);
            EXPECT_LT(clusters.order[p], root.end);
        }
    }
    const auto area = [&](const ClusterNode& node) {
        const auto outline = clusters.outline(node);
        double twice = 0;
        for (std::size_t k = 1; k + 1 < outline.size(); ++k)
            twice += cross(outline[k] - outline[0], outline[k + 1] - outline[0]).z;
        return 0.5 * std::fabs(twice);
    };
    const ClusterNode& root = clusters.cluster(0);
    EXPECT_GT(area(root), 0.9);  // a shuffled piece spans the floor
    for (uint32_t child : {root.firstChild, root.firstChild + 1}) {
        const ClusterNode& node = clusters.nodes[child];
        EXPECT_EQ(clusters.nodes[node.firstChild].begin, node.begin);
        EXPECT_EQ(clusters.nodes[node.firstChild + 1].end, node.end);
        for (uint32_t grandchild : {node.firstChild, node.firstChild + 1})
            EXPECT_LT(area(clusters.nodes[grandchild]), 0.3);
    }
}

}  // namespace
}  // namespace daisy
