#include "geometry/patch_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <utility>

#include "core/strings.h"
#include "geometry/subdivision.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

// Quads of their own four positions, so shared corners only meet through welding.
using verify::addQuad;

void addTriangle(TriangleMesh& mesh, Vec3d a, Vec3d b, Vec3d c) {
    const auto base = static_cast<uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), {a, b, c});
    mesh.triangles.push_back({base, base + 1, base + 2});
    mesh.materials.push_back(static_cast<uint32_t>(mesh.triangles.size()));
}

TriangleMesh unitSquare() {
    TriangleMesh mesh;
    addQuad(mesh, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});
    return mesh;
}

// The unit cube as 12 triangles, normals pointing inward (an enclosure).
TriangleMesh closedCube() {
    TriangleMesh mesh;
    verify::addCube(mesh, 0, 1, true);
    return mesh;
}

// Neighbours of very different sizes sharing an edge, a three-page non-manifold "book" on one
// edge, and a long thin sliver.
TriangleMesh mixedMesh() {
    TriangleMesh mesh;
    addTriangle(mesh, {0, 0, 0}, {1, 0, 0}, {0.5, 1, 0});
    addTriangle(mesh, {1, 0, 0}, {0, 0, 0}, {0.3, 0, 1});
    addTriangle(mesh, {0, 0, 0}, {1, 0, 0}, {0.7, -0.8, -0.4});
    addTriangle(mesh, {2, 0, 0}, {5, 0, 0}, {2, 3, 0});
    addTriangle(mesh, {2, 0, 0}, {2, 3, 0}, {1.8, 1.5, 0});
    addTriangle(mesh, {0, 2, 3}, {10, 2, 3}, {10, 2.05, 3});
    return mesh;
}

PatchMesh build(const TriangleMesh& mesh, double maxEdge) {
    auto patchMesh = buildPatchMesh(mesh, maxEdge);
    EXPECT_TRUE(patchMesh.ok()) << patchMesh.error().message;
    return std::move(*patchMesh);
}

using EdgeKey = std::pair<uint32_t, uint32_t>;

EdgeKey edgeOf(const PatchMesh& mesh, std::size_t patch, int k) {
    return {mesh.patches[patch][k], mesh.patches[patch][(k + 1) % 3]};
}

std::map<EdgeKey, int> undirectedEdgeUses(const PatchMesh& mesh) {
    std::map<EdgeKey, int> uses;
    for (std::size_t p = 0; p < mesh.patchCount(); ++p) {
        for (int k = 0; k < 3; ++k) {
            auto [a, b] = edgeOf(mesh, p, k);
            ++uses[{std::min(a, b), std::max(a, b)}];
        }
    }
    return uses;
}

double smallestAngle(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    auto angle = [](const Vec3d& apex, const Vec3d& p, const Vec3d& q) {
        return std::atan2(length(cross(p - apex, q - apex)), dot(p - apex, q - apex));
    };
    return std::min({angle(a, b, c), angle(b, c, a), angle(c, a, b)});
}

TEST(PatchMesh, KeepsTrianglesInSceneOrderWithoutSubdivision) {
    TriangleMesh mesh;
    // An unused position first and a -0 copy of the origin: welding drops the one, merges the
    // other.
    mesh.positions = {{9, 9, 9},    {0, 0, 0}, {1, 0, 0}, {1, 1, 0},
                      {-0.0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    mesh.triangles = {{1, 2, 3}, {4, 5, 6}};
    mesh.materials = {3, 7};
    const PatchMesh patches = build(mesh, 0);
    ASSERT_EQ(patches.patchCount(), 2u);
    ASSERT_EQ(patches.vertexCount(), 4u);  // a quad's four corners
    EXPECT_EQ(patches.positions[0], Vec3d(0, 0, 0));
    EXPECT_FALSE(std::signbit(patches.positions[0].x));
    EXPECT_EQ(patches.positions[3], Vec3d(0, 1, 0));  // numbered in first use
    EXPECT_EQ(patches.patches[0], (std::array<uint32_t, 3>{0, 1, 2}));
    EXPECT_EQ(patches.patches[1], (std::array<uint32_t, 3>{0, 2, 3}));
    EXPECT_EQ(patches.sourceTriangle, (std::vector<uint32_t>{0, 1}));
    EXPECT_EQ(patches.materials, (std::vector<uint32_t>{3, 7}));
    std::set<uint32_t> first(patches.patches[0].begin(), patches.patches[0].end());
    int shared = 0;
    for (uint32_t v : patches.patches[1])
        shared += first.count(v) ? 1 : 0;
    EXPECT_EQ(shared, 2);  // the diagonal
    // Half a unit square each, facing +z (counter-clockwise seen from +z).
    for (std::size_t p = 0; p < 2; ++p) {
        EXPECT_DOUBLE_EQ(patches.areas[p], 0.5);
        EXPECT_EQ(patches.normals[p], Vec3d(0, 0, 1));
    }
    EXPECT_NEAR(patches.centroids[0].x, 2.0 / 3, 1e-15);
    EXPECT_NEAR(patches.centroids[0].y, 1.0 / 3, 1e-15);
}

TEST(PatchMesh, RejectsNegativeAndNonFiniteMaxEdge) {
    const TriangleMesh mesh = unitSquare();
    for (double bad : {-0.1, std::nan(""), std::numeric_limits<double>::infinity()}) {
        auto result = buildPatchMesh(mesh, bad);
        ASSERT_FALSE(result.ok()) << bad;
        EXPECT_NE(result.error().message.find("--subdivide"), std::string::npos);
    }
}

TEST(PatchMesh, RefusesOverMaxPatchesBeforeAllocating) {
    // 1 m square at 10 um edges: ~2^33 patches, refused from the estimate alone.
    auto huge = buildPatchMesh(unitSquare(), 1e-5);
    ASSERT_FALSE(huge.ok());
    EXPECT_NE(huge.error().message.find("--subdivide"), std::string::npos) << huge.error().message;
    EXPECT_NE(huge.error().message.find(formatCount(estimatePatchCount(unitSquare(), 1e-5))),
              std::string::npos);
    // The limit applies to the estimate (an upper bound), not to the 64 patches made.
    const uint64_t bound = estimatePatchCount(unitSquare(), 0.25);
    EXPECT_FALSE(buildPatchMesh(unitSquare(), 0.25, bound - 1).ok());
    EXPECT_EQ(buildPatchMesh(unitSquare(), 0.25, bound)->patchCount(), 64u);
    EXPECT_FALSE(buildPatchMesh(unitSquare(), 0, 1).ok());
}

TEST(PatchMesh, AdjacencyMatchesBruteForceInversion) {
    const PatchMesh mesh = build(mixedMesh(), 0.4);
    ASSERT_EQ(mesh.vertexPatchOffsets.size(), mesh.vertexCount() + 1);
    for (uint32_t v = 0; v < mesh.vertexCount(); ++v) {
        std::vector<uint32_t> expected;
        for (uint32_t p = 0; p < mesh.patchCount(); ++p) {
            const auto& c = mesh.patches[p];
            if (c[0] == v || c[1] == v || c[2] == v) expected.push_back(p);
        }
        auto span = mesh.patchesAtVertex(v);
        EXPECT_EQ(std::vector<uint32_t>(span.begin(), span.end()), expected) << "vertex " << v;
    }
}

TEST(PatchMesh, EstimateBoundsTheActualCount) {
    struct Case {
        TriangleMesh mesh;
        double maxEdge;
        bool regular;  // a right isosceles grid: the bound is within 8x
    };
    TriangleMesh equilateral;
    addTriangle(equilateral, {0, 0, 0}, {1, 0, 0}, {0.5, std::sqrt(3.0) / 2, 0});
    const std::vector<Case> cases = {
        {unitSquare(), 0.3, true},   {unitSquare(), 0.1, true},  {unitSquare(), 0.01, true},
        {unitSquare(), 0.007, true}, {closedCube(), 0.05, true}, {equilateral, 0.05, false},
        {equilateral, 0.013, false}, {mixedMesh(), 0.2, false},  {mixedMesh(), 0.03, false},
        {mixedMesh(), 2.5, false},   {mixedMesh(), 100, false},
    };
    for (const Case& c : cases) {
        const uint64_t actual = build(c.mesh, c.maxEdge).patchCount();
        const uint64_t bound = estimatePatchCount(c.mesh, c.maxEdge);
        EXPECT_GE(bound, actual) << "maxEdge " << c.maxEdge;
        if (c.regular) {
            EXPECT_LE(bound, 8 * actual) << "maxEdge " << c.maxEdge;
        }
    }
    EXPECT_EQ(estimatePatchCount(mixedMesh(), 0), 6u);
}

TEST(PatchMesh, EstimateIsTightForSliversThinnerThanMaxEdge) {
    // A 2 m x 3 cm strip (a finely tessellated cylinder's side): the area bound grows like
    // (l / h)^2 here, so small slivers are counted exactly by the same bisection decisions.
    TriangleMesh strip;
    addQuad(strip, {0, 0, 0}, {0.03, 0, 0}, {0.03, 2, 0}, {0, 2, 0});
    for (double maxEdge : {0.05, 0.1, 0.5}) {
        EXPECT_EQ(estimatePatchCount(strip, maxEdge), build(strip, maxEdge).patchCount());
    }
}

TEST(Subdivision, UnitSquareBecomesRegularGrid) {
    // Longest-edge bisection keeps half-squares right isosceles; five levels take the hypotenuse
    // from sqrt(2) to 0.25: 2 x 2^5 = 64 patches of area 1/64, on the 5 x 5 corners of a 0.25 grid
    // plus its 16 cell centres (each cell cut by both diagonals).
    const PatchMesh mesh = build(unitSquare(), 0.25);
    ASSERT_EQ(mesh.patchCount(), 64u);
    EXPECT_EQ(mesh.vertexCount(), 41u);
    for (double area : mesh.areas)
        EXPECT_EQ(area, 1.0 / 64);
}

TEST(Subdivision, PreservesAreaNormalsAndSourceOrder) {
    const TriangleMesh input = mixedMesh();
    const double maxEdge = 0.15;
    const PatchMesh mesh = build(input, maxEdge);
    std::vector<double> childArea(input.triangleCount(), 0);
    double total = 0;
    for (std::size_t p = 0; p < mesh.patchCount(); ++p) {
        const uint32_t source = mesh.sourceTriangle[p];
        if (p > 0) {
            ASSERT_LE(mesh.sourceTriangle[p - 1], source) << "children not consecutive";
        }
        EXPECT_EQ(mesh.materials[p], input.materials[source]);
        childArea[source] += mesh.areas[p];
        total += mesh.areas[p];
        const Vec3d a = input.corner(source, 0), b = input.corner(source, 1);
        const Vec3d parentNormal = normalize(areaVector2(a, b, input.corner(source, 2)));
        EXPECT_NEAR(length(mesh.normals[p] - parentNormal), 0, 1e-12) << "patch " << p;
        for (int k = 0; k < 3; ++k) {
            auto [u, v] = edgeOf(mesh, p, k);
            EXPECT_LE(length(mesh.positions[u] - mesh.positions[v]), maxEdge);
        }
    }
    EXPECT_EQ(mesh.sourceTriangle.back(), input.triangleCount() - 1);
    // Conservation: bisection splits a triangle into two of exactly half its area.
    for (std::size_t t = 0; t < input.triangleCount(); ++t) {
        const double parent =
            triangleArea(input.corner(t, 0), input.corner(t, 1), input.corner(t, 2));
        EXPECT_NEAR(childArea[t], parent, 1e-12 * parent) << "triangle " << t;
    }
    EXPECT_NEAR(total, meshArea(input), 1e-12 * meshArea(input));
}

TEST(Subdivision, ClosedCubeStaysWatertight) {
    const PatchMesh mesh = build(closedCube(), 0.1);
    // Every undirected edge used exactly twice, each direction once (consistent winding).
    for (const auto& [edge, uses] : undirectedEdgeUses(mesh))
        EXPECT_EQ(uses, 2);
    std::set<EdgeKey> directed;
    for (std::size_t p = 0; p < mesh.patchCount(); ++p) {
        for (int k = 0; k < 3; ++k)
            EXPECT_TRUE(directed.insert(edgeOf(mesh, p, k)).second);
    }
    // Euler characteristic of a sphere: V - E + F = 2.
    const auto edges = static_cast<int64_t>(undirectedEdgeUses(mesh).size());
    EXPECT_EQ(int64_t(mesh.vertexCount()) - edges + int64_t(mesh.patchCount()), 2);
}

TEST(Subdivision, ConformingWithoutTJunctions) {
    const TriangleMesh input = mixedMesh();
    const PatchMesh mesh = build(input, 0.3);
    // The book's spine (0,0,0)-(1,0,0) carries three pages: its segments are used three times.
    // Elsewhere edges are interior (2) or on the boundary (1).
    for (const auto& [edge, uses] : undirectedEdgeUses(mesh)) {
        const Vec3d a = mesh.positions[edge.first], b = mesh.positions[edge.second];
        const bool onSpine = a.y == 0 && a.z == 0 && b.y == 0 && b.z == 0 && a.x <= 1 && b.x <= 1;
        if (onSpine) {
            EXPECT_EQ(uses, 3);
        } else {
            EXPECT_TRUE(uses == 1 || uses == 2) << uses;
        }
    }
    // No vertex lies strictly inside any patch edge.
    for (const auto& [edge, uses] : undirectedEdgeUses(mesh)) {
        const Vec3d a = mesh.positions[edge.first], d = mesh.positions[edge.second] - a;
        for (uint32_t v = 0; v < mesh.vertexCount(); ++v) {
            if (v == edge.first || v == edge.second) continue;
            const Vec3d r = mesh.positions[v] - a;
            const double t = dot(r, d) / dot(d, d);
            const bool onLine = length(cross(r, d)) <= 1e-12 * dot(d, d);
            EXPECT_FALSE(onLine && t > 0 && t < 1) << "vertex " << v << " on an edge";
        }
    }
}

TEST(Subdivision, LongThinTriangleKeepsRosenbergStengerAngleBound) {
    TriangleMesh input;
    addTriangle(input, {0, 0, 0}, {10, 0, 0}, {10, 0.05, 0});
    const double maxEdge = 0.1;
    const PatchMesh mesh = build(input, maxEdge);
    // Angles never drop below half the initial smallest angle (Rosenberg & Stenger 1975).
    const double alpha0 = smallestAngle(input.corner(0, 0), input.corner(0, 1), input.corner(0, 2));
    double area = 0;
    for (std::size_t p = 0; p < mesh.patchCount(); ++p) {
        const auto& c = mesh.patches[p];
        const Vec3d a = mesh.positions[c[0]], b = mesh.positions[c[1]], d = mesh.positions[c[2]];
        EXPECT_GE(smallestAngle(a, b, d), alpha0 / 2 * (1 - 1e-9));
        EXPECT_LE(std::max({length(b - a), length(d - b), length(a - d)}), maxEdge);
        area += mesh.areas[p];
    }
    EXPECT_NEAR(area, 0.25, 1e-12 * 0.25);  // 10 x 0.05 / 2
    EXPECT_GE(mesh.patchCount(), 100u);  // at least 10 / 0.1 along the long edge
}

TEST(Subdivision, IsDeterministic) {
    const PatchMesh first = build(mixedMesh(), 0.1);
    const PatchMesh second = build(mixedMesh(), 0.1);
    EXPECT_EQ(first.positions, second.positions);
    EXPECT_EQ(first.patches, second.patches);
}

TEST(Subdivision, StopsAtTheTriangleLimit) {
    std::vector<Vec3d> positions;
    VertexWelder welder(positions);
    const std::vector<std::array<uint32_t, 3>> triangles = {
        {welder.insert({0, 0, 0}), welder.insert({1, 0, 0}), welder.insert({1, 1, 0})}};
    EXPECT_EQ(bisectLongestEdges(triangles, 0.25, 32, welder)->triangles.size(), 32u);
    EXPECT_FALSE(bisectLongestEdges(triangles, 0.25, 31, welder).ok());
}

}  // namespace
}  // namespace daisy
