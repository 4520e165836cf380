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

}  // namespace
}  // namespace daisy
