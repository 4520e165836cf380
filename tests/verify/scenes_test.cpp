// The scene builders of verify/scenes.h: triangle counts, areas, normals and orders as their
// contracts state (each face normal is normalize(cross(b - a, c - a)), mesh.h), and groupFactor
// against a hand-summed matrix (F_AB = sum A_i F_ij / A_A, Howell, Menguc & Siegel, "Thermal
// Radiation Heat Transfer", 6th ed., section 4.3).
#include "verify/scenes.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "radiosity/matrix_transport.h"

namespace daisy::verify {
namespace {

double totalArea(const PatchMesh& mesh) {
    double sum = 0;
    for (double a : mesh.areas)
        sum += a;
    return sum;
}

void expectNormal(const PatchMesh& mesh, uint32_t begin, uint32_t end, Vec3d normal) {
    for (uint32_t p = begin; p < end; ++p) {
        EXPECT_NEAR(mesh.normals[p].x, normal.x, 1e-12) << "patch " << p;
        EXPECT_NEAR(mesh.normals[p].y, normal.y, 1e-12) << "patch " << p;
        EXPECT_NEAR(mesh.normals[p].z, normal.z, 1e-12) << "patch " << p;
    }
}

// Every patch of a closed box faces its centre (inward) or away from it (outward).
void expectFacing(const PatchMesh& mesh, Vec3d centre, bool inward) {
    for (uint32_t p = 0; p < mesh.patchCount(); ++p) {
        const double side = dot(mesh.normals[p], mesh.centroids[p] - centre);
        EXPECT_TRUE(inward ? side < 0 : side > 0) << "patch " << p;
    }
}

TEST(Scenes, GridIsRowsOfQuadsFacingCrossUV) {
    TriangleMesh mesh;
    addGrid(mesh, {1, 2, 3}, {2, 0, 0}, {0, 0, 3}, 3, 2, 7);  // normal cross(x, z) = -y
    EXPECT_EQ(mesh.triangleCount(), 12u);
    EXPECT_EQ(mesh.positions.size(), 12u);
    for (uint32_t material : mesh.materials)
        EXPECT_EQ(material, 7u);
    // The first quad's triangles: (0, 0) (1, 0) (1, 1) and (0, 0) (1, 1) (0, 1).
    EXPECT_EQ(mesh.triangles[0], (std::array<uint32_t, 3>{0, 1, 5}));
    EXPECT_EQ(mesh.triangles[1], (std::array<uint32_t, 3>{0, 5, 4}));
    const PatchMesh patches = patchesOf(mesh);
    EXPECT_NEAR(totalArea(patches), 6, 1e-12);
    expectNormal(patches, 0, 12, {0, -1, 0});
}

TEST(Scenes, QuadHasItsOwnFourCorners) {
    TriangleMesh mesh;
    addQuad(mesh, {0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}, 3);
    addQuad(mesh, {0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1});
    EXPECT_EQ(mesh.positions.size(), 8u);
    EXPECT_EQ(mesh.triangles[1], (std::array<uint32_t, 3>{0, 2, 3}));
    EXPECT_EQ(mesh.materials, (std::vector<uint32_t>{3, 3, 0, 0}));
    const PatchMesh patches = patchesOf(mesh);
    EXPECT_NEAR(patches.areas[0] + patches.areas[1], 2, 1e-12);
    expectNormal(patches, 0, 2, {0, 0, 1});
    expectNormal(patches, 2, 4, {1, 0, 0});
}

TEST(Scenes, UnitCubeRoomIsClosedAndFacesInwards) {
    const PatchMesh room = patchesOf(unitCubeRoom(3));
    EXPECT_EQ(room.patchCount(), 12u * 9);
    EXPECT_NEAR(totalArea(room), 6, 1e-12);
    expectFacing(room, {0.5, 0.5, 0.5}, true);
    expectNormal(room, 0, 18, {0, 0, 1});  // the floor first
    expectNormal(room, 18, 36, {0, 0, -1});
    for (uint32_t material : room.materials)
        EXPECT_EQ(material, 0u);
}

TEST(Scenes, RoomGivesEachFaceItsMaterial) {
    TriangleMesh mesh;
    addRoom(mesh, {1, 2, 3}, {2, 3, 4}, 2);
    const PatchMesh room = patchesOf(mesh);
    EXPECT_EQ(room.patchCount(), 48u);
    EXPECT_NEAR(totalArea(room), 2 * (6 + 8 + 12), 1e-12);
    expectFacing(room, {2, 3.5, 5}, true);
    for (uint32_t p = 0; p < 48; ++p)
        EXPECT_EQ(room.materials[p], p / 8);
    // Same triangles as the unit cube room when the box is the unit cube.
    TriangleMesh unit;
    addRoom(unit, {0, 0, 0}, {1, 1, 1}, 2);
    EXPECT_EQ(unit.positions, unitCubeRoom(2).positions);
    EXPECT_EQ(unit.triangles, unitCubeRoom(2).triangles);
}

TEST(Scenes, SolidBoxFacesOutwards) {
    TriangleMesh mesh;
    addSolidBox(mesh, {0.35, 0.35, 0.2}, {0.3, 0.3, 0.3}, 2);
    const PatchMesh box = patchesOf(mesh);
    EXPECT_EQ(box.patchCount(), 48u);
    EXPECT_NEAR(totalArea(box), 6 * 0.09, 1e-12);
    expectFacing(box, {0.5, 0.5, 0.35}, false);
    expectNormal(box, 0, 8, {0, 0, -1});
}

TEST(Scenes, CubeFacesInwardsOrOutwards) {
    for (bool inward : {true, false}) {
        TriangleMesh mesh;
        addCube(mesh, -1, 2, inward);
        const PatchMesh cube = patchesOf(mesh);
        EXPECT_EQ(cube.patchCount(), 12u);
        EXPECT_NEAR(totalArea(cube), 54, 1e-12);
        expectFacing(cube, {0.5, 0.5, 0.5}, inward);
        expectNormal(cube, 0, 2, {inward ? 1.0 : -1.0, 0, 0});  // x = lo first
    }
}

TEST(Scenes, ClosedRoomFacesInwards) {
    const PatchMesh room = patchesOf(closedRoom({-1, 0, -2}, {3, 2, 2}));
    EXPECT_EQ(room.patchCount(), 12u);
    EXPECT_NEAR(totalArea(room), 2 * (16 + 8 + 8), 1e-12);
    expectFacing(room, {1, 1, 0}, true);
    expectNormal(room, 0, 2, {0, 1, 0});  // the floor y = lo first
}

TEST(Scenes, HowellSquares) {
    const PatchMesh parallel = patchesOf(parallelSquares(2, 3));
    EXPECT_EQ(parallel.patchCount(), 16u);
    expectNormal(parallel, 0, 8, {0, 0, 1});
    expectNormal(parallel, 8, 16, {0, 0, -1});
    for (uint32_t p = 8; p < 16; ++p)
        EXPECT_EQ(parallel.centroids[p].z, 3);
    const PatchMesh perpendicular = patchesOf(perpendicularSquares(2));
    EXPECT_EQ(perpendicular.patchCount(), 16u);
    expectNormal(perpendicular, 0, 8, {0, 0, 1});
    expectNormal(perpendicular, 8, 16, {1, 0, 0});
    EXPECT_NEAR(totalArea(perpendicular), 2, 1e-12);
    const PatchMesh half = patchesOf(halfOccludedSquares());
    EXPECT_EQ(half.patchCount(), 258u);
    expectNormal(half, 256, 258, {0, 0, 1});
    EXPECT_NEAR(half.areas[256] + half.areas[257], 4.5, 1e-12);
    EXPECT_EQ(half.centroids[256].z, 1);
}

TEST(Scenes, GroupFactorIsTheAreaWeightedSum) {
    // Two triangles of area 1/2 (patches 0, 1) and two at distance 1 (patches 2, 3).
    const PatchMesh mesh = patchesOf(parallelSquares(1));
    SparseMatrix f = SparseMatrix::zeros(4);
    f.columns = {2, 3, 0, 3};  // row 0: F_02, F_03; row 1: F_10, F_13
    f.values = {0.125f, 0.0625f, 0.5f, 0.25f};
    f.rowOffsets = {0, 2, 4, 4, 4};
    ASSERT_EQ(validateStructure(f), "");
    const MatrixTransport transport(f);
    // (0.5 (0.125 + 0.0625) + 0.5 (0.25)) / 1; F_10 lies outside [2, 4).
    EXPECT_DOUBLE_EQ(groupFactor(mesh, transport, 0, 2, 2, 4), 0.21875);
    EXPECT_DOUBLE_EQ(groupFactor(mesh, transport, 1, 2, 0, 1), 0.5);
    EXPECT_DOUBLE_EQ(groupFactor(mesh, transport, 2, 4, 0, 4), 0);
}

}  // namespace
}  // namespace daisy::verify
