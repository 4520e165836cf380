#include "pipeline/vertex_radiance.h"

#include <gtest/gtest.h>

#include <vector>

#include "verify/scenes.h"

namespace daisy {
namespace {

// Corner value of `vertex` (by position) on patch p.
float cornerAt(const PatchMesh& mesh, const std::vector<float>& corners, uint32_t p,
               const Vec3d& position, int channels = 1, int channel = 0) {
    for (int c = 0; c < 3; ++c) {
        if (mesh.positions[mesh.patches[p][c]] == position)
            return corners[(p * 3 + c) * channels + channel];
    }
    ADD_FAILURE() << "patch " << p << " has no corner at " << position;
    return 0;
}

// Two coplanar triangles of one material sharing the edge (0,0)-(1,1): at the shared corners
// both see the area-weighted mean (A1 v1 + A2 v2) / (A1 + A2); at their own corners only
// themselves.
TEST(ImageVertexRadiance, CoplanarSameMaterialAveragesByArea) {
    TriangleMesh triangles;
    triangles.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-2, 1, 0}};
    triangles.triangles = {{0, 1, 2}, {0, 2, 3}};  // areas 0.5 and 1.5
    triangles.materials = {0, 0};
    const PatchMesh mesh = verify::patchesOf(triangles);
    ASSERT_EQ(mesh.patchCount(), 2u);
    const std::vector<float> values = {2, 10, 4, 8};  // patch 0 = (2, 10), patch 1 = (4, 8)
    const std::vector<float> corners = cornerValues(mesh, values, 2);
    ASSERT_EQ(corners.size(), 2u * 3 * 2);
    const double a0 = mesh.areas[0], a1 = mesh.areas[1];
    EXPECT_NEAR(a0, 0.5, 1e-12);
    EXPECT_NEAR(a1, 1.5, 1e-12);
    const float mean0 = static_cast<float>((a0 * 2 + a1 * 4) / (a0 + a1));
    const float mean1 = static_cast<float>((a0 * 10 + a1 * 8) / (a0 + a1));
    for (const Vec3d& shared : {Vec3d(0, 0, 0), Vec3d(1, 1, 0)}) {
        for (uint32_t p : {0u, 1u}) {
            EXPECT_FLOAT_EQ(cornerAt(mesh, corners, p, shared, 2, 0), mean0);
            EXPECT_FLOAT_EQ(cornerAt(mesh, corners, p, shared, 2, 1), mean1);
        }
    }
    EXPECT_FLOAT_EQ(cornerAt(mesh, corners, 0, {1, 0, 0}, 2, 0), 2);
    EXPECT_FLOAT_EQ(cornerAt(mesh, corners, 1, {-2, 1, 0}, 2, 1), 8);
}

TEST(ImageVertexRadiance, CreaseAndMaterialBoundaryAreNotMixed) {
    // Floor quad (y = 0) and a wall quad (x = 0) meeting at a 90 degree crease along the z
    // axis, plus a coplanar floor quad of another material beside the first.
    TriangleMesh triangles;
    verify::addQuad(triangles, {0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}, 0);  // floor, +y
    verify::addQuad(triangles, {0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}, 0);  // wall, +x
    verify::addQuad(triangles, {1, 0, 0}, {1, 0, 1}, {2, 0, 1}, {2, 0, 0}, 1);  // floor, other
    const PatchMesh mesh = verify::patchesOf(triangles);
    ASSERT_EQ(mesh.patchCount(), 6u);
    const std::vector<float> values = {1, 1, 5, 5, 9, 9};  // per quad
    const std::vector<float> corners = cornerValues(mesh, values, 1);
    for (uint32_t p = 0; p < 6; ++p) {
        for (int c = 0; c < 3; ++c)
            EXPECT_FLOAT_EQ(corners[p * 3 + c], values[p]) << "patch " << p << " corner " << c;
    }
    // With a crease angle above 90 degrees the floor and wall do mix at the shared edge.
    const std::vector<float> smooth = cornerValues(mesh, values, 1, 2.0);
    EXPECT_GT(cornerAt(mesh, smooth, 0, {0, 0, 0}), 1.0f);
    EXPECT_LT(cornerAt(mesh, smooth, 0, {0, 0, 0}), 5.0f);
}

}  // namespace
}  // namespace daisy
