#include "scene/validate_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "scene/load_scene.h"
#include "test_util.h"

namespace daisy {
namespace {

Scene twoTriangles() {
    Scene scene;
    scene.path = "mem.gltf";
    scene.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    scene.mesh.triangles = {{0, 1, 2}, {1, 3, 2}};
    scene.mesh.materials = {0, 0};
    Material material;
    material.name = "white";
    material.origin = "mem.gltf: materials[0]";
    material.emissiveRgb = {1, 1, 1};  // an emitter, so no "no surface emits light" warning
    scene.materials.push_back(material);
    return scene;
}

TEST(ValidateScene, KeepsAGoodSceneUnchanged) {
    Scene scene = twoTriangles();
    ASSERT_TRUE(validateScene(scene));
    EXPECT_EQ(scene.mesh.triangleCount(), 2u);
    EXPECT_EQ(scene.degenerateDropped, 0u);
    EXPECT_TRUE(scene.warnings.empty());
}

TEST(ValidateScene, DropsZeroAreaTrianglesAndWarns) {
    Scene scene = twoTriangles();
    scene.mesh.positions.push_back({2, 0, 0});
    scene.mesh.triangles.push_back({0, 1, 4});  // collinear: area exactly 0
    scene.mesh.triangles.push_back({0, 0, 3});  // repeated corner
    scene.mesh.materials.insert(scene.mesh.materials.end(), {0, 0});
    ASSERT_TRUE(validateScene(scene));
    EXPECT_EQ(scene.mesh.triangleCount(), 2u);
    EXPECT_EQ(scene.degenerateDropped, 2u);
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_NE(scene.warnings[0].find("dropped 2 degenerate"), std::string::npos);
}

TEST(ValidateScene, KeepsSlivers) {
    // Aspect ratio 1e4 (the stress suite's slivers) is thin but not degenerate.
    Scene scene = twoTriangles();
    scene.mesh.positions.push_back({1, 1e-4, 0});
    scene.mesh.triangles.push_back({0, 1, 4});
    scene.mesh.materials.push_back(0);
    ASSERT_TRUE(validateScene(scene));
    EXPECT_EQ(scene.mesh.triangleCount(), 3u);
}

TEST(ValidateScene, RefusesNonFinitePositions) {
    Scene scene = twoTriangles();
    scene.mesh.positions[3].y = std::numeric_limits<double>::quiet_NaN();
    auto result = validateScene(scene);
    ASSERT_FALSE(result);
    EXPECT_NE(result.error().message.find("mem.gltf: vertex 3"), std::string::npos);
}

TEST(ValidateScene, RefusesOutOfRangeIndices) {
    Scene scene = twoTriangles();
    scene.mesh.triangles[1][2] = 9;
    auto result = validateScene(scene);
    ASSERT_FALSE(result);
    EXPECT_NE(result.error().message.find("triangle 1 uses vertex 9 of 4"), std::string::npos);

    scene = twoTriangles();
    scene.mesh.materials[0] = 5;
    result = validateScene(scene);
    ASSERT_FALSE(result);
    EXPECT_NE(result.error().message.find("triangle 0 uses material 5 of 1"), std::string::npos);
}

TEST(ValidateScene, RefusesReflectanceOutsideUnitRangeAndNegativeEmission) {
    Scene scene = twoTriangles();
    scene.materials[0].baseColor = {0.5, 1.2, 0.5};
    auto result = validateScene(scene);
    ASSERT_FALSE(result);
    EXPECT_NE(result.error().message.find("materials[0]: reflectance component 1 is 1.2"),
              std::string::npos);

    scene = twoTriangles();
    scene.materials[0].emissiveRgb = {0, -1, 0};
    result = validateScene(scene);
    ASSERT_FALSE(result);
    EXPECT_NE(result.error().message.find("emission component 1"), std::string::npos);
}

TEST(ValidateScene, RefusesASceneWithNothingLeft) {
    Scene scene = twoTriangles();
    scene.mesh.triangles = {{0, 0, 1}};
    scene.mesh.materials = {0};
    auto result = validateScene(scene);
    ASSERT_FALSE(result);
    EXPECT_NE(result.error().message.find("no triangles with non-zero area"), std::string::npos);
}

TEST(LoadScene, RefusesMissingFilesAndUnknownFormats) {
    auto missing = loadScene("/nonexistent/box.gltf");
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.error().message, "/nonexistent/box.gltf: no such file");

    const auto dir = test::testTempDir();
    const std::string ply = test::writeFile(dir, "box.ply", "ply\n");
    auto unknown = loadScene(ply);
    ASSERT_FALSE(unknown);
    EXPECT_NE(unknown.error().message.find("unknown scene format '.ply'"), std::string::npos);
}

// The committed measured Cornell box (tools/make_cornell_box.py): 15 quads as 30 triangles and
// the ceiling as a ring of 8 around the light, in metres, inside the measured extent
// 556.0 x 548.8 x 559.2 mm.
TEST(LoadScene, MeasuredCornellBox) {
    auto scene = loadScene(test::assetPath("scenes/cornell_box.gltf"));
    ASSERT_TRUE(scene) << scene.error().message;
    EXPECT_EQ(scene->mesh.triangleCount(), 38u);
    EXPECT_EQ(scene->degenerateDropped, 0u);
    const Bounds3d bounds = meshBounds(scene->mesh);
    EXPECT_NEAR(bounds.lo.x, 0.0, 1e-9);
    EXPECT_NEAR(bounds.hi.x, 0.556, 1e-7);
    EXPECT_NEAR(bounds.hi.y, 0.5488, 1e-7);
    EXPECT_NEAR(bounds.hi.z, 0.5592, 1e-7);
    ASSERT_EQ(scene->materials.size(), 4u);
    EXPECT_EQ(scene->materials[3].name, "emitter");
    EXPECT_TRUE(scene->materials[3].isEmissive());
    EXPECT_FALSE(scene->materials[0].isEmissive());
    ASSERT_TRUE(scene->materials[1].spectral.reflectance);
    const auto* table =
        std::get_if<TabulatedSpectrum>(&scene->materials[1].spectral.reflectance->shape);
    ASSERT_NE(table, nullptr);
    EXPECT_EQ(table->wavelengthsNm.size(), 76u);  // 400..700 nm in 4 nm steps
    ASSERT_EQ(scene->cameras.size(), 1u);
    // 35 mm lens on 25 mm film: yfov = 2 atan(12.5 / 35).
    EXPECT_NEAR(scene->cameras[0].yFovRad, 2 * std::atan(12.5 / 35), 1e-8);
    EXPECT_NEAR(scene->cameras[0].forward.z, 1.0, 1e-12);
    EXPECT_NEAR(scene->cameras[0].position.z, -0.8, 1e-7);
    // Every wall (floor, light, ceiling ring, back, right, left) faces the room's centre (the
    // box is open towards -z).
    const Vec3d roomCentre{0.278, 0.2744, 0.2796};
    for (std::size_t t = 0; t < 18; ++t) {
        const Vec3d a = scene->mesh.corner(t, 0), b = scene->mesh.corner(t, 1),
                    c = scene->mesh.corner(t, 2);
        EXPECT_GT(dot(areaVector2(a, b, c), roomCentre - (a + b + c) / 3.0), 0) << t;
    }
}

}  // namespace
}  // namespace daisy
