#include "geometry/auto_patch_size.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include "core/strings.h"
#include "geometry/patch_mesh.h"
#include "scene/load_scene.h"
#include "test_util.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

using verify::addQuad;

TriangleMesh unitSquare() {
    TriangleMesh mesh;
    addQuad(mesh, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});
    return mesh;
}

TEST(AutoPatchSize, EmptyMeshKeepsNothingToSplit) {
    const AutoPatchSize size = chooseAutoPatchSize(TriangleMesh{});
    EXPECT_EQ(size.maxEdge, 0);
    EXPECT_EQ(size.budget, kAutoPatchBudget);
}

// The rule: the smallest size whose patch count fits the budget. Longest-edge bisection of a
// square's two right triangles doubles the count at each step (2, 4, 8, ...), so the count is
// a power of two at most the budget, and 2% smaller edges would break the budget.
TEST(AutoPatchSize, SquareFillsTheBudgetAndNoMore) {
    const TriangleMesh mesh = unitSquare();
    const AutoPatchSize size = chooseAutoPatchSize(mesh);
    ASSERT_GT(size.maxEdge, 0);
    auto patches = buildPatchMesh(mesh, size.maxEdge);
    ASSERT_TRUE(patches) << patches.error().message;
    EXPECT_EQ(patches->patchCount(), size.patches);
    EXPECT_LE(patches->patchCount(), kAutoPatchBudget);
    EXPECT_GE(patches->patchCount(), kAutoPatchBudget / 2);
    auto finer = buildPatchMesh(mesh, size.maxEdge * 0.98);
    ASSERT_TRUE(finer);
    EXPECT_GT(finer->patchCount(), kAutoPatchBudget);
}

// The size is rounded to 3 significant digits, so the number the summary prints reproduces it
// through --subdivide.
TEST(AutoPatchSize, PrintedSizeReproducesIt) {
    TriangleMesh mesh;
    addQuad(mesh, {0, 0, 0}, {0.37, 0, 0}, {0.37, 0.29, 0}, {0, 0.29, 0});
    const AutoPatchSize size = chooseAutoPatchSize(mesh, 1000);
    ASSERT_GT(size.maxEdge, 0);
    EXPECT_EQ(std::strtod(formatNumber(size.maxEdge, 3).c_str(), nullptr), size.maxEdge);
}

TEST(AutoPatchSize, SceneAtOrOverTheBudgetKeepsItsTriangles) {
    const TriangleMesh mesh = unitSquare();
    EXPECT_EQ(chooseAutoPatchSize(mesh, 2).maxEdge, 0);
    EXPECT_EQ(chooseAutoPatchSize(mesh, 1).maxEdge, 0);
}

// Large triangles are split, small ones kept: a 1 m square next to a 1 cm one.
TEST(AutoPatchSize, SplitsLargeTrianglesFirst) {
    TriangleMesh mesh = unitSquare();
    addQuad(mesh, {2, 0, 0}, {2.01, 0, 0}, {2.01, 0.01, 0}, {2, 0.01, 0});
    const AutoPatchSize size = chooseAutoPatchSize(mesh, 600);
    ASSERT_GT(size.maxEdge, 0.015);
    auto patches = buildPatchMesh(mesh, size.maxEdge);
    ASSERT_TRUE(patches);
    std::size_t small = 0;
    for (uint32_t source : patches->sourceTriangle)
        small += source >= 2;
    EXPECT_EQ(small, 2u);
    EXPECT_LE(patches->patchCount(), 600u);
}

// The demo scenes: the measured Cornell box (two triangles a wall, 0.55 m) gets
// patches of a few centimetres; the 7,712-triangle black-light box is kept as it is.
TEST(AutoPatchSize, DemoScenes) {
    auto cornell = loadScene(test::assetPath("scenes/cornell_box.gltf"));
    ASSERT_TRUE(cornell) << cornell.error().message;
    const AutoPatchSize size = chooseAutoPatchSize(cornell->mesh);
    EXPECT_GT(size.maxEdge, 0.01);
    EXPECT_LT(size.maxEdge, 0.06);
    auto patches = buildPatchMesh(cornell->mesh, size.maxEdge);
    ASSERT_TRUE(patches);
    EXPECT_EQ(patches->patchCount(), size.patches);
    EXPECT_GE(patches->patchCount(), kAutoPatchBudget * 3 / 4);
    EXPECT_LE(patches->patchCount(), kAutoPatchBudget);

    auto box = loadScene(test::assetPath("scenes/blacklight_box.gltf"));
    ASSERT_TRUE(box) << box.error().message;
    EXPECT_EQ(chooseAutoPatchSize(box->mesh).maxEdge, 0);
}

}  // namespace
}  // namespace daisy
