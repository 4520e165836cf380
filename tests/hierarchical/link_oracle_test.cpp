// The oracle's geometric decision (hierarchical/link_oracle.h) on hand-made node pairs whose
// bound is known in closed form, and the importance weights on a two-sample system.
#include "hierarchical/link_oracle.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <vector>

#include "geometry/patch_mesh.h"
#include "hierarchical/cluster_tree.h"
#include "radiosity/solver_test_util.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

// A planar node of `count` patches: a square of side `side` at height z facing +z (up) or -z,
// its corners' box, sphere and slab.
HierarchyNode square(double z, double side, bool up, uint32_t count = 2) {
    HierarchyNode node;
    node.count = count;
    node.boxLo = {0, 0, z};
    node.boxHi = {side, side, z};
    node.center = node.centroid = {side / 2, side / 2, z};
    node.radius = side / std::sqrt(2.0);
    node.area = side * side;
    node.coneAxis = {0, 0, up ? 1.0 : -1.0};
    node.coneCos = 1;
    node.normalLo = node.normalHi = node.coneAxis;
    node.slabLo = node.slabHi = up ? z : -z;
    return node;
}

// A planar node of 2 patches: the unit square in the plane x = `x` from z = `z` up to z + 1,
// facing -x, its box, sphere and slab.
HierarchyNode wallFacingMinusX(double x, double z) {
    HierarchyNode wall;
    wall.count = 2;
    wall.boxLo = {x, 0, z};
    wall.boxHi = {x, 1, z + 1};
    wall.center = wall.centroid = {x, 0.5, z + 0.5};
    wall.radius = std::sqrt(0.5);
    wall.area = 1;
    wall.coneAxis = {-1, 0, 0};
    wall.coneCos = 1;
    wall.normalLo = wall.normalHi = wall.coneAxis;
    wall.slabLo = wall.slabHi = -x;
    return wall;
}

// Two unit squares 10 apart, facing: Phi = C (s_S y_R + s_R y_S) with C = A_R A_S / (pi gap^2),
// gap = 10 - 2 / sqrt(2); the bound is Phi rho / d. A far link exactly when the bound is at
// most epsilon; above it, the side with the larger share is split (equal shares: R).
TEST(LinkOracle, AFarLinkExactlyWhenTheBoundIsUnderEpsilon) {
    const HierarchyNode r = square(0, 1, true), s = square(10, 1, false);
    const LinkWeights weights{2, 0.5, 3, 0.25};
    const double rho = 2 / std::sqrt(2.0), gap = 10 - rho;
    const double power = (3 * 0.5 + 2 * 0.25) / (M_PI * gap * gap);
    const double bound = power * rho / 10;
    const LinkDecision at = chooseLink(r, s, weights, bound * (1 + 1e-12), 0.25);
    EXPECT_EQ(at.choice, LinkChoice::Far);
    EXPECT_NEAR(at.power, power, 1e-15);
    EXPECT_NEAR(at.error, bound, 1e-15);
    EXPECT_EQ(chooseLink(r, s, weights, bound * (1 - 1e-9), 0.25).choice,
              LinkChoice::SplitReceiver);
    // The aperture: rho / d = 0.141 passes 0.25 and fails 0.1 while the pair's whole exchange
    // may pass epsilon (kFarEstimateBound Phi); once it cannot, a far link at any aperture.
    EXPECT_EQ(chooseLink(r, s, weights, power, 0.1).choice, LinkChoice::SplitReceiver);
    EXPECT_EQ(chooseLink(r, s, weights, kFarEstimateBound * power * (1 - 1e-9), 0.1).choice,
              LinkChoice::SplitReceiver);
    const LinkDecision whole = chooseLink(r, s, weights, kFarEstimateBound * power, 0.1);
    EXPECT_EQ(whole.choice, LinkChoice::Far);
    EXPECT_NEAR(whole.error, kFarEstimateBound * power, 1e-15);
    // Leaves are split never: two leaves over the bound become a near link.
    const HierarchyNode leafR = square(0, 1, true, 1), leafS = square(10, 1, false, 1);
    EXPECT_EQ(chooseLink(leafR, leafS, weights, bound * 0.5, 0.25).choice, LinkChoice::Near);
}

// Facing: the upper square turned up (its back to the lower one), or the two in one plane,
// exchange nothing whatever the bound; a square over a wall standing on its plane faces it.
TEST(LinkOracle, PairsFacingAwayOrCoplanarExchangeNothing) {
    const LinkWeights weights{1, 1, 1, 1};
    EXPECT_EQ(chooseLink(square(0, 1, true), square(10, 1, true), weights, 1e9, 0.25).choice,
              LinkChoice::None);
    HierarchyNode beside = square(0, 1, true);
    beside.boxLo.x += 3, beside.boxHi.x += 3, beside.center.x += 3, beside.centroid.x += 3;
    EXPECT_EQ(chooseLink(square(0, 1, true), beside, weights, 1e9, 0.25).choice, LinkChoice::None);
    const HierarchyNode wall = wallFacingMinusX(20, 0);  // facing the square
    EXPECT_EQ(chooseLink(square(0, 1, true), wall, weights, 1e9, 0.25).choice, LinkChoice::Far);
}

// A floor square running past the plane of a wall above it (the wall x = 2, facing -x, from
// z = 0.5 up; the floor 0 <= x <= 3 at z = -4, facing +z): the wall faces the floor in part.
// Over epsilon the pair is split (the wall, the side that faces in part); once the pair's whole
// exchange is within epsilon, a far link when each centroid lies in front of the other's plane
// (the floor's centroid x = 1.5 is in front of the wall), and also when one does not (a floor
// from x = 1.2 to 4.2 has its centroid behind the wall): two planar nodes, whose link is
// weighed by its segments (hierarchical_links.h); a curved side facing away from the
// centroids' direction gets nothing.
TEST(LinkOracle, APairFacingInPartIsLinkedOnceItsWholeExchangeIsWithinEpsilon) {
    const LinkWeights weights{1, 1, 1, 1};
    const HierarchyNode wall = wallFacingMinusX(2, 0.5);
    const HierarchyNode floor = square(-4, 3, true);
    HierarchyNode past = floor;
    past.boxLo.x += 1.2, past.boxHi.x += 1.2, past.center.x += 1.2, past.centroid.x += 1.2;
    const LinkDecision over = chooseLink(floor, wall, weights, 1e-9, 0.25);
    EXPECT_EQ(over.choice, LinkChoice::SplitSource);
    ASSERT_GT(over.power, 0);
    const double epsilon = kFarEstimateBound * over.power;
    const LinkDecision linked = chooseLink(floor, wall, weights, epsilon, 0.25);
    EXPECT_EQ(linked.choice, LinkChoice::Far);
    EXPECT_NEAR(linked.error, epsilon, 1e-12 * epsilon);
    EXPECT_EQ(chooseLink(floor, wall, weights, epsilon * (1 - 1e-9), 0.25).choice,
              LinkChoice::SplitSource);
    EXPECT_EQ(chooseLink(past, wall, weights, 1e9, 0.25).choice, LinkChoice::Far);
    HierarchyNode curvedWall = wall;
    curvedWall.coneCos = 0.99;
    curvedWall.normalLo = {-1, -0.1, -0.1};
    curvedWall.normalHi = {-0.99, 0.1, 0.1};
    ASSERT_FALSE(curvedWall.isPlanar());
    EXPECT_EQ(chooseLink(past, curvedWall, weights, 1e9, 0.25).choice, LinkChoice::None);
}

// A curved node (normals within 60 degrees of +z, as a stretch of a vault seen from below) under
// a square 10 above and 3 aside: every normal faces the direction between the centroids (16.7
// degrees off the axis), but not every direction to the square's sphere (rho / d = 0.25 adds
// 14.5 degrees), so over epsilon the curved side is split; once the pair's whole exchange is
// within epsilon, a far link (every cosine along the centroids' direction is positive).
TEST(LinkOracle, ACurvedNodeFacingTheCentroidsDirectionIsLinkedWithinEpsilon) {
    HierarchyNode curved;
    curved.count = 2;
    curved.boxLo = {-0.35, -0.35, -0.1};
    curved.boxHi = {0.35, 0.35, 0.1};
    curved.center = curved.centroid = {0, 0, 0};
    curved.radius = 0.5;
    curved.area = 0.5;
    curved.coneAxis = {0, 0, 1};
    curved.coneCos = 0.5;
    curved.normalLo = {-std::sqrt(0.75), -std::sqrt(0.75), 0.5};
    curved.normalHi = {std::sqrt(0.75), std::sqrt(0.75), 1};
    curved.slabLo = -0.5, curved.slabHi = 0.5;
    ASSERT_FALSE(curved.isPlanar());
    HierarchyNode above = square(10, 3, false);
    for (Vec3d* p : {&above.boxLo, &above.boxHi, &above.center, &above.centroid})
        p->x += 1.5, p->y -= 1.5;
    const LinkWeights weights{1, 1, 1, 1};
    const LinkDecision over = chooseLink(curved, above, weights, 1e-12, 0.25);
    EXPECT_EQ(over.choice, LinkChoice::SplitReceiver);
    ASSERT_GT(over.power, 0);
    EXPECT_EQ(chooseLink(curved, above, weights, kFarEstimateBound * over.power, 0.25).choice,
              LinkChoice::Far);
    EXPECT_EQ(chooseLink(curved, above, weights, over.power, 0.25).choice,
              LinkChoice::SplitReceiver);
}

// A strip of a barrel vault along z: its normals on an arc of 20 degrees round -y across the
// barrel (none along it), and a leaf 12 down the barrel and 0.5 lower facing back along -z.
// Every normal faces every direction to the leaf's sphere (n . u >= 0.0416 cos 10 degrees
// against a chord of 0.033), but the cone round the arc (10 degrees) also holds normals tilted
// along z, which would not: by the cone alone the strip faced the leaf in part and was split
// down to its patches; by the box of its normals it is linked.
TEST(LinkOracle, AVaultStripFacesAPointDownTheBarrelByItsNormalsBox) {
    const double tilt = 10 * M_PI / 180;
    HierarchyNode strip;
    strip.count = 4;
    strip.boxLo = {-0.2, -0.05, -0.2};
    strip.boxHi = {0.2, 0.0, 0.2};
    strip.center = strip.centroid = {0, -0.025, 0};
    strip.radius = 0.29;
    strip.area = 0.16;
    strip.coneAxis = {0, -1, 0};
    strip.coneCos = std::cos(tilt);
    strip.normalLo = {-std::sin(tilt), -1, 0};
    strip.normalHi = {std::sin(tilt), -std::cos(tilt), 0};
    strip.slabLo = -0.29, strip.slabHi = 0.29;
    ASSERT_FALSE(strip.isPlanar());
    HierarchyNode leaf;
    leaf.boxLo = {-0.05, -0.6, 12};
    leaf.boxHi = {0.05, -0.5, 12};
    leaf.center = leaf.centroid = {0, -0.55, 12};
    leaf.radius = std::sqrt(0.05 * 0.05 * 2);
    leaf.area = 0.01;
    leaf.coneAxis = leaf.normalLo = leaf.normalHi = {0, 0, -1};
    leaf.slabLo = leaf.slabHi = -12;
    const LinkWeights weights{1, 1, 1, 1};
    EXPECT_EQ(chooseLink(strip, leaf, weights, 1e9, 0.25).choice, LinkChoice::Far);
    HierarchyNode coneOnly = strip;
    coneOnly.normalLo = {-1, -1, -1};
    coneOnly.normalHi = {1, 1, 1};
    EXPECT_EQ(chooseLink(coneOnly, leaf, weights, 1e9, 0.25).choice, LinkChoice::SplitReceiver);
    // Turned over (normals round +y) every normal faces away from the leaf: nothing.
    HierarchyNode over = strip;
    over.coneAxis = {0, 1, 0};
    over.normalLo = {-std::sin(tilt), std::cos(tilt), 0};
    over.normalHi = {std::sin(tilt), 1, 0};
    EXPECT_EQ(chooseLink(over, leaf, weights, 1e9, 0.25).choice, LinkChoice::None);
}

// The tree's box of normals is each node's least and greatest normal components over its
// patches, on a polygonal half cylinder (a vault of 12 facets, 4 patches each).
TEST(LinkOracle, TheClusterTreeBoundsEveryNodesNormalsByTheirBox) {
    TriangleMesh mesh;
    const int facets = 12;
    for (int f = 0; f < facets; ++f) {
        const double a0 = M_PI * f / facets, a1 = M_PI * (f + 1) / facets;
        for (int z = 0; z < 2; ++z) {
            const uint32_t base = uint32_t(mesh.positions.size());
            mesh.positions.push_back({std::cos(a0), std::sin(a0), double(z)});
            mesh.positions.push_back({std::cos(a1), std::sin(a1), double(z)});
            mesh.positions.push_back({std::cos(a1), std::sin(a1), double(z + 1)});
            mesh.positions.push_back({std::cos(a0), std::sin(a0), double(z + 1)});
            mesh.triangles.push_back({base, base + 2, base + 1});
            mesh.triangles.push_back({base, base + 3, base + 2});
            mesh.materials.insert(mesh.materials.end(), 2, 0);
        }
    }
    auto patches = buildPatchMesh(mesh, 0);
    ASSERT_TRUE(patches.ok()) << patches.error().message;
    const ClusterTree tree = buildClusterTree(*patches);
    ASSERT_EQ(tree.nodes.size(), 2 * patches->patchCount() - 1);
    for (const HierarchyNode& node : tree.nodes) {
        Vec3d lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
        for (uint32_t k = node.first; k < node.first + node.count; ++k) {
            const Vec3d& n = patches->normals[tree.order[k]];
            for (int c = 0; c < 3; ++c)
                lo[c] = std::min(lo[c], n[c]), hi[c] = std::max(hi[c], n[c]);
        }
        for (int c = 0; c < 3; ++c) {
            EXPECT_EQ(node.normalLo[c], lo[c]);
            EXPECT_EQ(node.normalHi[c], hi[c]);
        }
        EXPECT_LT(std::abs(node.normalLo.z), 1e-12);  // no normal along the barrel
        EXPECT_LT(std::abs(node.normalHi.z), 1e-12);
    }
}

// The far gather's tree passes: every node visited once, after both children (pull) or before
// them (push), with subtrees of up to 3 patches run serially and the rest split in parallel.
TEST(LinkOracle, SubtreeVisitsReachEveryNodeOnceInTreeOrder) {
    const PatchMesh patches = verify::patchesOf(verify::unitCubeRoom(16));
    const ClusterTree tree = buildClusterTree(patches);
    ASSERT_EQ(tree.nodes.size(), 2 * patches.patchCount() - 1);
    for (const bool childrenFirst : {true, false}) {
        std::atomic<uint32_t> clock{0};
        std::vector<std::atomic<uint32_t>> visited(tree.nodes.size());
        std::vector<uint32_t> when(tree.nodes.size(), 0);
        visitSubtrees(
            tree,
            [&](std::size_t k) {
                when[k] = clock++;
                ++visited[k];
            },
            childrenFirst, 3);
        for (std::size_t k = 0; k < tree.nodes.size(); ++k) {
            ASSERT_EQ(visited[k].load(), 1u) << "node " << k;
            for (const uint32_t child : tree.nodes[k].children) {
                if (child == kNoNode) continue;
                EXPECT_EQ(when[child] < when[k], childrenFirst) << "node " << k;
            }
        }
    }
}

// A thick planar slab: the undersides of two shelves facing down (-z), at z = 1 and z = 3, and
// a wall between their heights (x = 0.5, z from 1.5 to 2.5, facing -x): the wall lies behind
// the upper shelf's plane but in front of the lower one's, so the pair faces in part and must be
// split, not dropped (it was dropped as "behind or within" the slab, losing up to 38% of some
// patches' rows on the black-light box).
TEST(LinkOracle, AThickSlabFacesWhatLiesBetweenItsFaces) {
    HierarchyNode shelves = square(1, 1, false);
    shelves.boxHi.z = 3;
    shelves.center.z = shelves.centroid.z = 2;
    shelves.radius = std::sqrt(0.5 + 1.0);
    shelves.slabLo = -3, shelves.slabHi = -1;
    const LinkWeights weights{1, 1, 1, 1};
    EXPECT_EQ(chooseLink(shelves, wallFacingMinusX(0.5, 1.5), weights, 1e9, 0.25).choice,
              LinkChoice::SplitReceiver);
    // Wholly above the upper shelf's plane it is behind every face: nothing.
    EXPECT_EQ(chooseLink(shelves, wallFacingMinusX(0.5, 3.5), weights, 1e9, 0.25).choice,
              LinkChoice::None);
}

// Two samples, 550 nm (ybar ~ 1) and 365 nm (ybar ~ 0): a white material's yield is 1 and a
// black one's 0; UV light is worth nothing without a fluorescent material, and what the
// fluorescent one makes of it (0.4 of it re-emitted at 550 nm) with one.
TEST(LinkOracle, ImportanceWeighsUvByTheVisibleLightItCanBecome) {
    using solvertest::matrixOperator;
    RadiositySystem system = solvertest::makeSystem(
        2, 2, {matrixOperator(2, {0.9, 0, 0, 0.9}), matrixOperator(2, {0, 0, 0.4, 0})});
    system.wavelengthsNm = {365, 550};
    system.patchOperator = {0, 1};
    system.emission = {1, 0, 0, 0};  // patch 0 emits UV only
    const LinkImportance withFluorescence = linkImportance(system);
    EXPECT_GT(withFluorescence.source[0], 0);
    EXPECT_NEAR(withFluorescence.yield[1], 1.0, 1e-12);  // all of its UV's worth becomes visible
    system.operators[1] = matrixOperator(2, {0, 0, 0, 0});
    const LinkImportance without = linkImportance(system);
    EXPECT_NEAR(without.source[0], 0, 1e-3 * withFluorescence.source[0]);
    EXPECT_EQ(without.yield[1], 0);
}

// Links refined for one light stay valid under another unless some patch's share of the visible
// power, or its yield, grew past the factor: scaling every source leaves every share; a share
// from 0 (a new lamp) or a yield grown 1.5x (a grey material made white) does not.
TEST(LinkOracle, LinksAreOutdatedWhenAShareOfTheLightGrows) {
    LinkImportance before;
    before.source = {4, 1, 0};
    before.yield = {0.5, 0.5, 0.2};
    before.totalPower = 5;
    LinkImportance after = before;
    for (double& s : after.source)
        s *= 3;
    after.totalPower *= 3;
    EXPECT_FALSE(importanceGrew(before, after, 1.4));
    after.source[1] *= 1.3;  // its share grows 1.23x (the total grows too)
    after.totalPower += 0.3 * 3;
    EXPECT_FALSE(importanceGrew(before, after, 1.4));
    after.source[1] *= 1.2;  // 1.47x
    EXPECT_TRUE(importanceGrew(before, after, 1.4));
    after = before;
    after.source[2] = 1e-6;
    EXPECT_TRUE(importanceGrew(before, after, 1.4));
    after = before;
    after.yield[0] = 0.75;
    EXPECT_TRUE(importanceGrew(before, after, 1.4));
    after.yield[0] = 0.69;
    EXPECT_FALSE(importanceGrew(before, after, 1.4));
    after.totalPower = 0;  // no light: nothing to carry
    after.yield[0] = 1;
    EXPECT_FALSE(importanceGrew(before, after, 1.4));
}

}  // namespace
}  // namespace daisy
