// Exposed parts of patches (radiosity/patch_exposure.h): a closed box standing on a subdivided
// floor, single- or double-sided, buries exactly the floor's quadrature points inside its
// footprint (the oracle is the footprint itself: a point is under the box or not), and nothing
// else; a table, a room's shell and a lamp's shade bury nothing; an open scene, where no point
// is inside anything, is exposed everywhere.
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

// The floor's expected exposed points under the footprint (x0, x1) x (y0, y1).
uint16_t outsideFootprint(const PatchMesh& patches, std::size_t p, float x0, float x1, float y0,
                          float y1) {
    const shared::PatchGeometry t = geometryOf(patches, p);
    uint16_t expected = 0;
    for (int q = 0; q < kPatchQuadraturePoints; ++q) {
        const shared::vec3 x = patchQuadraturePoint(t, q);
        const bool under = x.x > x0 && x.x < x1 && x.y > y0 && x.y < y1;
        if (!under) expected = uint16_t(expected | (1u << q));
    }
    return expected;
}

// Material 1 (from triangle `first` on) double-sided, as Blender writes every material.
PatchMesh doubleSidedFrom(TriangleMesh mesh, std::size_t first) {
    for (std::size_t t = first; t < mesh.materials.size(); ++t)
        mesh.materials[t] = 1;
    const std::vector<uint8_t> doubleSided = {0, 1};
    return std::move(buildPatchMesh(mesh, 0, UINT32_MAX, doubleSided).value());
}

// A closed double-sided box on the floor: from a floor point under it, every probe meets the
// box's faces from within, where they are double-sided (no back face to tell), so the box
// buries exactly the footprint as the single-sided box above does. Its outer faces stay
// exposed; its inner faces (the back patches) are buried.
TEST(PatchExposure, ADoubleSidedBoxBuriesExactlyTheFootprint) {
    TriangleMesh mesh;
    verify::addGrid(mesh, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 4, 4);
    const std::size_t floor = mesh.triangleCount();
    verify::addSolidBox(mesh, {0.3, 0.3, 0}, {0.4, 0.4, 0.3});
    const PatchMesh patches = doubleSidedFrom(mesh, floor);
    ASSERT_GT(patches.patchCount(), floor + 12);  // the box's back patches
    auto exposure = patchExposure(patches);
    ASSERT_TRUE(exposure.ok()) << exposure.error().message;
    int partly = 0;
    for (std::size_t p = 0; p < patches.patchCount(); ++p) {
        const bool inner = p >= floor + 12;  // the box's back patches follow its 12 fronts
        const uint16_t expected = p < floor ? outsideFootprint(patches, p, 0.3f, 0.7f, 0.3f, 0.7f)
            : inner                         ? uint16_t(0)
                                            : uint16_t(0xffff);
        EXPECT_EQ(exposure->exposedPoints[p], expected) << "patch " << p;
        partly += p < floor && expected != 0xffff;
    }
    EXPECT_EQ(patches.patchCount(), floor + 24);
    EXPECT_EQ(partly, 8);
}

// What is not a closed object buries nothing: a double-sided table top 0.3 over the floor (the
// probes at 80 degrees leave from under it), a double-sided room shell facing out round the
// whole scene (a piece over half the scene's size), and an emitter under a double-sided shade
// (an open-bottomed box whose faces enclose it: without the emitter flag it is buried).
TEST(PatchExposure, TablesShellsAndShadedEmittersAreNotBuried) {
    {
        TriangleMesh mesh;
        verify::addGrid(mesh, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, 8, 8);
        const std::size_t floor = mesh.triangleCount();
        verify::addQuad(mesh, {1.6, 1.6, 0.3}, {2.4, 1.6, 0.3}, {2.4, 2.4, 0.3}, {1.6, 2.4, 0.3});
        auto exposure = patchExposure(doubleSidedFrom(mesh, floor));
        ASSERT_TRUE(exposure.ok());
        for (const float phi : exposure->fraction)
            EXPECT_EQ(phi, 1.0f);
    }
    {
        TriangleMesh mesh;
        verify::addGrid(mesh, {0.25, 0.25, 0.3}, {0.5, 0, 0}, {0, 0.5, 0}, 2, 2);
        const std::size_t floor = mesh.triangleCount();
        verify::addCube(mesh, 0, 1, false);  // the shell: faces out
        auto exposure = patchExposure(doubleSidedFrom(mesh, floor));
        ASSERT_TRUE(exposure.ok());
        for (const float phi : exposure->fraction)
            EXPECT_EQ(phi, 1.0f);
    }
    TriangleMesh mesh;
    verify::addGrid(mesh, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, 1, 1);  // a floor far below
    verify::addQuad(mesh, {1.7, 1.7, 1}, {2.3, 1.7, 1}, {2.3, 2.3, 1}, {1.7, 2.3, 1});  // facing up
    const std::size_t lamp = mesh.triangleCount();
    TriangleMesh shade;
    verify::addSolidBox(shade, {1.6, 1.6, 0.99}, {0.8, 0.8, 0.3});
    for (std::size_t t = 2; t < shade.triangleCount(); ++t) {  // without its bottom (z = 0.99)
        const auto& c = shade.triangles[t];
        mesh.triangles.push_back({uint32_t(mesh.positions.size()),
                                  uint32_t(mesh.positions.size() + 1),
                                  uint32_t(mesh.positions.size() + 2)});
        mesh.materials.push_back(0);
        for (int k = 0; k < 3; ++k)
            mesh.positions.push_back(shade.positions[c[std::size_t(k)]]);
    }
    const PatchMesh patches = doubleSidedFrom(mesh, lamp);
    std::vector<uint8_t> emitters(patches.patchCount(), 0);
    emitters[2] = emitters[3] = 1;  // the lamp's two triangles
    auto lit = patchExposure(patches, emitters);
    auto unlit = patchExposure(patches);
    ASSERT_TRUE(lit.ok() && unlit.ok());
    for (std::size_t p = 0; p < patches.patchCount(); ++p)
        EXPECT_EQ(lit->fraction[p], 1.0f) << "patch " << p;
    EXPECT_EQ(unlit->fraction[2], 0.0f);
    EXPECT_EQ(unlit->fraction[3], 0.0f);
    // A point light inside a closed double-sided box lights the floor under it.
    TriangleMesh room;
    verify::addGrid(room, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, 1, 1);
    verify::addSolidBox(room, {1, 1, 0}, {1, 1, 1});
    const PatchMesh boxed = doubleSidedFrom(room, 2);
    const Vec3d light{1.5, 1.5, 0.5};
    auto dark = patchExposure(boxed);
    auto inside = patchExposure(boxed, {}, std::span(&light, 1));
    ASSERT_TRUE(dark.ok() && inside.ok());
    EXPECT_LT(dark->fraction[0] + dark->fraction[1], 2.0f);
    for (std::size_t p = 0; p < boxed.patchCount(); ++p)
        EXPECT_EQ(inside->fraction[p], 1.0f) << "patch " << p;
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
