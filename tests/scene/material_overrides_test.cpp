#include "scene/material_overrides.h"

#include <gtest/gtest.h>

#include <string>

#include "test_util.h"

namespace daisy {
namespace {

Material makeMaterial(const std::string& name) {
    Material material;
    material.name = name;
    material.origin = "room.obj: material '" + name + "'";
    return material;
}

// Three materials, two of them named "paint".
Scene makeScene() {
    Scene scene;
    scene.path = "room.obj";
    scene.materials = {makeMaterial("wall"), makeMaterial("paint"), makeMaterial("paint")};
    scene.materials[1].spectral.emission = SpectrumSpec{PresetSpectrum{"D65"}, 2.0};
    return scene;
}

TEST(MaterialOverrides, ReplacesReflectanceOfEveryMaterialWithTheName) {
    Scene scene = makeScene();
    const auto path = test::writeFile(test::testTempDir(), "materials.json",
                                      R"({"paint": {"reflectance": {"rgb": [0.1, 0.2, 0.3]}}})");
    auto applied = applyMaterialOverrides(scene, path);
    ASSERT_TRUE(applied.ok()) << applied.error().message;

    for (int m : {1, 2}) {
        ASSERT_TRUE(scene.materials[m].spectral.reflectance) << m;
        EXPECT_EQ(std::get<RgbSpectrum>(scene.materials[m].spectral.reflectance->shape).rgb,
                  (std::array<double, 3>{0.1, 0.2, 0.3}));
    }
    // Members the file does not set stay as they were (mergeExtension).
    ASSERT_TRUE(scene.materials[1].spectral.emission);
    EXPECT_EQ(std::get<PresetSpectrum>(scene.materials[1].spectral.emission->shape).name, "D65");
    EXPECT_EQ(scene.materials[1].spectral.emission->scale, 2.0);
    EXPECT_FALSE(scene.materials[0].spectral.reflectance);
}

TEST(MaterialOverrides, ReplacesAnExistingReflectance) {
    Scene scene = makeScene();
    scene.materials[0].spectral.reflectance = SpectrumSpec{RgbSpectrum{{1, 1, 1}}, 1.0};
    const auto path = test::writeFile(test::testTempDir(), "materials.json", R"({"wall":
        {"reflectance": {"wavelengths": [400, 700], "values": [0.2, 0.6]}}})");
    auto applied = applyMaterialOverrides(scene, path);
    ASSERT_TRUE(applied.ok()) << applied.error().message;
    const auto& table = std::get<TabulatedSpectrum>(scene.materials[0].spectral.reflectance->shape);
    EXPECT_EQ(table.values, (std::vector<double>{0.2, 0.6}));
}

TEST(MaterialOverrides, UnknownNameListsTheSceneMaterials) {
    Scene scene = makeScene();
    const auto path = test::writeFile(test::testTempDir(), "materials.json",
                                      R"({"floor": {"reflectance": {"rgb": [0, 0, 0]}}})");
    auto applied = applyMaterialOverrides(scene, path);
    ASSERT_FALSE(applied.ok());
    EXPECT_EQ(applied.error().message,
              path + ": material 'floor' is not in room.obj (it has: wall, paint)");
}

TEST(MaterialOverrides, MalformedJsonNamesTheFileAndLine) {
    Scene scene = makeScene();
    const auto path = test::writeFile(test::testTempDir(), "materials.json",
                                      "{\"paint\": {\"reflectance\":\n  {\"rgb\": [0, 0, 0]}},\n}");
    auto applied = applyMaterialOverrides(scene, path);
    ASSERT_FALSE(applied.ok());
    const std::string& message = applied.error().message;
    EXPECT_EQ(message.rfind(path + ": invalid JSON", 0), 0u) << message;
    EXPECT_NE(message.find("line 3"), std::string::npos) << message;
}

TEST(MaterialOverrides, MissingFileAndWrongTopLevel) {
    Scene scene = makeScene();
    const auto dir = test::testTempDir();
    const std::string missing = (dir / "nope.json").string();
    auto applied = applyMaterialOverrides(scene, missing);
    ASSERT_FALSE(applied.ok());
    EXPECT_EQ(applied.error().message, missing + ": no such file");

    const auto path = test::writeFile(dir, "array.json", "[1, 2]");
    auto array = applyMaterialOverrides(scene, path);
    ASSERT_FALSE(array.ok());
    EXPECT_EQ(array.error().message,
              path +
                  ": expected an object mapping material names to DAISY_materials_spectral "
                  "objects, got array");
}

TEST(MaterialOverrides, ExtensionErrorsCarryFileAndPath) {
    Scene scene = makeScene();
    const auto path = test::writeFile(test::testTempDir(), "materials.json",
                                      R"({"paint": {"reflectance": {"rgb": [1.5, 0, 0]}}})");
    auto applied = applyMaterialOverrides(scene, path);
    ASSERT_FALSE(applied.ok());
    EXPECT_EQ(applied.error().message, path + ": paint.reflectance.rgb[0]: 1.5 is outside [0, 1]");
}

TEST(MaterialOverrides, NamesThatAreNotIdentifiersAreQuotedInPaths) {
    Scene scene = makeScene();
    scene.materials.push_back(makeMaterial("my.paint"));
    const auto path = test::writeFile(test::testTempDir(), "materials.json",
                                      R"({"my.paint": {"emission": {"blackbody": 1}}})");
    auto applied = applyMaterialOverrides(scene, path);
    ASSERT_FALSE(applied.ok());
    EXPECT_EQ(applied.error().message,
              path + ": [\"my.paint\"].emission.blackbody: 1 K is outside [100, 100000] K");
}

TEST(MaterialOverrides, AnErrorLeavesTheSceneUntouched) {
    Scene scene = makeScene();
    // "paint" is valid and parsed first (nlohmann::json keeps members sorted by name); "wall" is
    // not, so nothing may be applied.
    const auto path = test::writeFile(test::testTempDir(), "materials.json", R"({
        "paint": {"reflectance": {"rgb": [0.1, 0.2, 0.3]}},
        "wall": {"fluorescence": {"preset": "glowstick"}}})");
    auto applied = applyMaterialOverrides(scene, path);
    ASSERT_FALSE(applied.ok());
    EXPECT_NE(applied.error().message.find("wall.fluorescence.preset"), std::string::npos);
    EXPECT_FALSE(scene.materials[1].spectral.reflectance);
    EXPECT_FALSE(scene.materials[2].spectral.reflectance);
}

}  // namespace
}  // namespace daisy
