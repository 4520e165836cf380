// Exposed parts of patches (radiosity/patch_exposure.h): a closed box standing on a subdivided
// floor buries exactly the floor's quadrature points inside its footprint (the oracle is the
// footprint itself: a point is under the box or not), and nothing else; an open scene, where no
// point is inside anything, is exposed everywhere.
#include <gtest/gtest.h>

#include <bit>
#include <numeric>

#include "geometry/patch_mesh.h"
#include "radiosity/patch_exposure.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

shared::PatchGeometry geometryOf(const PatchMesh& patches, std::size_t p) {
    const auto& c = patches.patches[p];
    const auto v = [&](int k) {
        const Vec3d& x = patches.positions[c[std::size_t(k)]];
        return shared::vec3{float(x.x), float(x.y), float(x.z)};
    };
    return shared::makePatchGeometry(v(0), v(1), v(2));
}

TEST(PatchExposure, BoxOnAFloorBuriesExactlyTheFootprint) {
    TriangleMesh mesh;
    verify::addGrid(mesh, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 4, 4);  // 32 floor patches, +z
    // Footprint [0.3, 0.7]^2: no quadrature point of the 0.25 cells lies on its outline.
    verify::addSolidBox(mesh, {0.3, 0.3, 0}, {0.4, 0.4, 0.3});
    const PatchMesh patches = verify::patchesOf(mesh);
    auto exposure = patchExposure(patches);
    ASSERT_TRUE(exposure.ok()) << exposure.error().message;
    int buried = 0, partly = 0;
    for (std::size_t p = 0; p < patches.patchCount(); ++p) {
        uint16_t expected = 0xffff;
        if (p < 32) {
            const shared::PatchGeometry t = geometryOf(patches, p);
            expected = 0;
            for (int q = 0; q < kPatchQuadraturePoints; ++q) {
                const shared::vec3 x = patchQuadraturePoint(t, q);
                const bool under = x.x > 0.3f && x.x < 0.7f && x.y > 0.3f && x.y < 0.7f;
                if (!under) expected = uint16_t(expected | (1u << q));
            }
        }
        EXPECT_EQ(exposure->exposedPoints[p], expected) << "patch " << p;
        const int exposed = std::popcount(unsigned(expected));
        EXPECT_FLOAT_EQ(exposure->fraction[p], exposed / 16.0f);
        buried += exposed == 0;
        partly += exposed > 0 && exposed < 16;
    }
    // No cell lies wholly under the box; both triangles of each of the four middle cells
    // straddle its outline.
    EXPECT_EQ(buried, 0);
    EXPECT_EQ(partly, 8);
    const std::vector<double> areas = exposedAreas(patches, *exposure);
    EXPECT_NEAR(std::accumulate(areas.begin(), areas.begin() + 32, 0.0), 1 - 0.16, 0.03);
}

TEST(PatchExposure, EveryPointOfAnOpenSceneIsExposed) {
    const PatchMesh patches = verify::patchesOf(verify::perpendicularSquares(3));
    auto exposure = patchExposure(patches);
    ASSERT_TRUE(exposure.ok());
    for (std::size_t p = 0; p < patches.patchCount(); ++p) {
        EXPECT_EQ(exposure->exposedPoints[p], 0xffff);
        EXPECT_EQ(exposure->fraction[p], 1.0f);
    }
}

// The 16 children tile the triangle: a uniform point of child q (pointInPatchChild) lies in the
// triangle, in the child's own quarter-grid cell, and the children's points average to the
// child's centroid, patchQuadraturePoint (to the sample mean's accuracy), so sampling a patch's
// exposed children is sampling its exposed area.
TEST(PatchExposure, ChildPointsTileThePatchAroundTheQuadraturePoints) {
    const shared::vec3 a{0, 0, 0}, b{2, 0, 0}, c{0.5f, 1.5f, 0};
    const shared::PatchGeometry t = shared::makePatchGeometry(a, b, c);
    constexpr int kSide = 64;  // a 64 x 64 grid of u
    for (int q = 0; q < kPatchQuadraturePoints; ++q) {
        const shared::vec3 centroid = patchQuadraturePoint(t, q);
        double mean[2] = {0, 0};
        for (int i = 0; i < kSide; ++i) {
            for (int j = 0; j < kSide; ++j) {
                const shared::vec2 u((i + 0.5f) / kSide, (j + 0.5f) / kSide);
                const shared::vec3 x = pointInPatchChild(a, b, c, q, u);
                // Barycentric weights of b and c (x = a + wb (b - a) + wc (c - a)).
                const double wc = x.y / 1.5, wb = (x.x - 0.5 * wc) / 2;
                EXPECT_GE(wb, -1e-6);
                EXPECT_GE(wc, -1e-6);
                EXPECT_LE(wb + wc, 1 + 1e-6);
                // In the child's cell: its corners' weights, in quarters, differ by at most 1.
                const double cb = (centroid.x - 0.5 * centroid.y / 1.5) / 2, cc = centroid.y / 1.5;
                EXPECT_LE(std::abs(wb - cb), 0.25 * 2.0 / 3 + 1e-6) << "child " << q;
                EXPECT_LE(std::abs(wc - cc), 0.25 * 2.0 / 3 + 1e-6) << "child " << q;
                mean[0] += x.x, mean[1] += x.y;
            }
        }
        EXPECT_NEAR(mean[0] / (kSide * kSide), centroid.x, 2e-3) << "child " << q;
        EXPECT_NEAR(mean[1] / (kSide * kSide), centroid.y, 2e-3) << "child " << q;
    }
}

}  // namespace
}  // namespace daisy
