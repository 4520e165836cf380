// `--edit NAME.FIELD=VALUE` (viewer/material_edit.h): parsed by the scene loader's extension
// parser, so the values and the messages are the file format's.
#if DAISY_HAVE_VIEWER
#include "viewer/material_edit.h"

#include <gtest/gtest.h>

#include <variant>

namespace daisy::viewer {
namespace {

TEST(MaterialEdit, RgbReflectance) {
    auto edit = parseMaterialEdit("red.reflectance=rgb(0, 1, 0.25)");
    ASSERT_TRUE(edit) << edit.error().message;
    EXPECT_EQ(edit->materialName, "red");
    ASSERT_TRUE(edit->extension.reflectance);
    const auto* rgb = std::get_if<RgbSpectrum>(&edit->extension.reflectance->shape);
    ASSERT_NE(rgb, nullptr);
    EXPECT_EQ(rgb->rgb, (std::array<double, 3>{0, 1, 0.25}));
    EXPECT_FALSE(edit->extension.emission);
    EXPECT_FALSE(edit->extension.fluorescence);
}

TEST(MaterialEdit, JsonMembersAndDottedNames) {
    auto lamp = parseMaterialEdit("my.lamp.emission={\"blackbody\": 2700, \"scale\": 5}");
    ASSERT_TRUE(lamp) << lamp.error().message;
    EXPECT_EQ(lamp->materialName, "my.lamp");
    ASSERT_TRUE(lamp->extension.emission);
    EXPECT_EQ(lamp->extension.emission->scale, 5);
    const auto* blackbody = std::get_if<BlackbodySpectrum>(&lamp->extension.emission->shape);
    ASSERT_NE(blackbody, nullptr);
    EXPECT_EQ(blackbody->temperatureK, 2700);

    auto paper = parseMaterialEdit("paper.fluorescence={\"preset\": \"fluorescein\"}");
    ASSERT_TRUE(paper) << paper.error().message;
    ASSERT_TRUE(paper->extension.fluorescence);
    EXPECT_TRUE(std::holds_alternative<FluorophorePreset>(*paper->extension.fluorescence));
}

TEST(MaterialEdit, BadEditsSayWhatIsWrong) {
    for (const auto& [text, says] :
         {std::pair<std::string, std::string>{"red", "NAME.FIELD=VALUE"},
          {"red.colour=rgb(1,0,0)", "'colour'"},
          {"red.reflectance=rgb(2,0,0)", "outside [0, 1]"},
          {"red.reflectance=rgb(1,0", "--edit 'red.reflectance=rgb(1,0'"},
          {".reflectance=rgb(1,0,0)", "NAME.FIELD=VALUE"}}) {
        auto edit = parseMaterialEdit(text);
        ASSERT_FALSE(edit) << text;
        EXPECT_NE(edit.error().message.find(says), std::string::npos)
            << text << ": " << edit.error().message;
    }
}

TEST(MaterialEdit, TargetsEveryMaterialOfTheNameOrListsTheNames) {
    Scene scene;
    scene.path = "box.gltf";
    for (const char* name : {"wall", "lamp", "wall"}) {
        Material material;
        material.name = name;
        scene.materials.push_back(material);
    }
    auto edit = parseMaterialEdit("wall.reflectance=rgb(0,1,0)");
    ASSERT_TRUE(edit);
    auto targets = editTargets(scene, *edit);
    ASSERT_TRUE(targets);
    EXPECT_EQ(*targets, (std::vector<std::size_t>{0, 2}));
    const Material edited = applyEdit(scene.materials[0], *edit);
    EXPECT_TRUE(edited.spectral.reflectance);

    auto missing = parseMaterialEdit("floor.reflectance=rgb(0,1,0)");
    ASSERT_TRUE(missing);
    auto none = editTargets(scene, *missing);
    ASSERT_FALSE(none);
    EXPECT_NE(none.error().message.find("box.gltf has no material 'floor' (it has 'wall', 'lamp')"),
              std::string::npos)
        << none.error().message;
}

}  // namespace
}  // namespace daisy::viewer
#endif
