#include "radiosity/matrix_estimate.h"

#include <gtest/gtest.h>

#include <cmath>

#include "verify/scenes.h"

namespace daisy {
namespace {

using verify::addCube;
using verify::addQuad;

PatchMesh build(const TriangleMesh& mesh, double maxEdge) {
    auto patchMesh = buildPatchMesh(mesh, maxEdge);
    EXPECT_TRUE(patchMesh.ok()) << patchMesh.error().message;
    return std::move(*patchMesh);
}

TEST(MatrixEstimate, ClosedRoomFacesAllButItsOwnFace) {
    // Inward unit cube, 12 triangles. Two triangles on one face are coplanar (dot = 0: not
    // facing). Any two faces face: for opposite faces trivially; for adjacent ones, e.g. the
    // floor (n = +z) and the wall x = 0 (n = +x), dot(n_floor, c_wall - c_floor) = z_wall > 0 and
    // dot(n_wall, c_floor - c_wall) = x_floor > 0. So each triangle faces the 10 triangles off its
    // face: 12 x 10 = 120 of the 12 x 11 = 132 ordered pairs, 10/11.
    TriangleMesh room;
    addCube(room, 0, 1, true);
    const MatrixEstimate estimate = estimateMatrixMemory(build(room, 0));
    EXPECT_EQ(estimate.patchCount, 12u);
    EXPECT_FALSE(estimate.sampled);
    EXPECT_DOUBLE_EQ(estimate.facingFraction, 10.0 / 11);
    EXPECT_EQ(estimate.nonzeros, 120u);
    EXPECT_EQ(estimate.matrixBytes, 8u * 13 + 8u * 120);  // CSR offsets + (column, value) pairs
}

TEST(MatrixEstimate, ConvexObjectSeenFromOutsideHasNoFacingPairs) {
    // Outward normals of a convex body: every other centroid is behind each face's plane.
    TriangleMesh box;
    addCube(box, 0, 1, false);
    const MatrixEstimate estimate = estimateMatrixMemory(build(box, 0));
    EXPECT_EQ(estimate.facingFraction, 0);
    EXPECT_EQ(estimate.nonzeros, 0u);
    EXPECT_EQ(estimate.matrixBytes, 8u * 13);
}

TEST(MatrixEstimate, TwoParallelFacingQuads) {
    // Floor (n = +z) under a ceiling (n = -z) one unit up: the 2 x 2 cross pairs face in both
    // orders (8 ordered pairs); the pairs within a quad are coplanar. 8 of 4 x 3 = 12: 2/3.
    TriangleMesh mesh;
    addQuad(mesh, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});
    addQuad(mesh, {0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1});
    const PatchMesh patches = build(mesh, 0);
    ASSERT_EQ(patches.normals[2], Vec3d(0, 0, -1));
    const MatrixEstimate estimate = estimateMatrixMemory(patches);
    EXPECT_DOUBLE_EQ(estimate.facingFraction, 2.0 / 3);
    EXPECT_EQ(estimate.nonzeros, 8u);
    EXPECT_EQ(estimate.matrixBytes, 8u * 5 + 8u * 8);
}

TEST(MatrixEstimate, EmptyAndSinglePatchMeshes) {
    const MatrixEstimate empty = estimateMatrixMemory(PatchMesh{});
    EXPECT_EQ(empty.nonzeros, 0u);
    EXPECT_EQ(empty.matrixBytes, 8u);  // the one row offset
    TriangleMesh one;
    one.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    one.triangles = {{0, 1, 2}};
    const MatrixEstimate single = estimateMatrixMemory(build(one, 0));
    EXPECT_EQ(single.facingFraction, 0);
    EXPECT_EQ(single.matrixBytes, 16u);
}

TEST(MatrixEstimate, SampledFractionMatchesExactCount) {
    // A room with a box in it, ~3300 patches: over the exact-count limit, so 200,000 sampled
    // pairs (standard error ~0.001) must land within 0.01 of the brute-force fraction.
    TriangleMesh scene;
    addCube(scene, 0, 1, true);
    addCube(scene, 0.4, 0.6, false);
    const PatchMesh mesh = build(scene, 0.1);
    ASSERT_GT(mesh.patchCount(), 3000u);
    uint64_t facingPairs = 0;
    for (std::size_t i = 0; i < mesh.patchCount(); ++i) {
        for (std::size_t j = 0; j < mesh.patchCount(); ++j) {
            const Vec3d d = mesh.centroids[j] - mesh.centroids[i];
            facingPairs += i != j && dot(mesh.normals[i], d) > 0 && dot(mesh.normals[j], d) < 0;
        }
    }
    const double n = static_cast<double>(mesh.patchCount());
    const double exact = facingPairs / (n * (n - 1));
    const MatrixEstimate estimate = estimateMatrixMemory(mesh);
    EXPECT_TRUE(estimate.sampled);
    EXPECT_NEAR(estimate.facingFraction, exact, 0.01);
    EXPECT_NEAR(static_cast<double>(estimate.nonzeros), exact * n * (n - 1), 0.01 * n * (n - 1));
    EXPECT_EQ(estimate.matrixBytes, 8 * (mesh.patchCount() + 1) + 8 * estimate.nonzeros);
    // Fixed seed: the same answer every time.
    EXPECT_EQ(estimateMatrixMemory(mesh).facingFraction, estimate.facingFraction);
}

}  // namespace
}  // namespace daisy
