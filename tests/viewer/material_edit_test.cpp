// `--edit NAME.FIELD=VALUE` (viewer/material_edit.h): parsed by the scene loader's extension
// parser, so the values and the messages are the file format's.
#if DAISY_HAVE_VIEWER
#include "viewer/material_edit.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <variant>

#include "pipeline/session.h"
#include "scene/material_extension.h"
#include "verify/scenes.h"

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

// The panel's drafts become the extension's own types; the physical check is the session's, so
// a draft with reflectance + absorption over 1 is refused there (DESIGN.md section 5).
TEST(MaterialEdit, DraftsBecomeMaterialsTheSessionChecks) {
    Material base;
    base.name = "wall";
    base.origin = "room: material 0";
    base.baseColor = {0.25, 0.5, 0.75};
    MaterialDraft draft = draftOf(base);
    EXPECT_EQ(draft.reflectanceRgb, (std::array<float, 3>{0.25f, 0.5f, 0.75f}));
    EXPECT_FLOAT_EQ(draft.reflectancePoints[3], 0.5f);

    draft.spectralReflectance = true;
    draft.reflectancePoints = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f, 0.7f, 0.8f};
    draft.emissionKind = 3;
    draft.blackbodyK = 2700;
    draft.emissionScale = 4;
    draft.fluorescenceKind = 2;
    draft.fluorescencePreset = 1;
    const Material built = materialFromDraft(base, draft);
    const auto* points = std::get_if<TabulatedSpectrum>(&built.spectral.reflectance->shape);
    ASSERT_NE(points, nullptr);
    EXPECT_EQ(points->wavelengthsNm.front(), 350);
    EXPECT_EQ(points->wavelengthsNm.back(), 700);
    EXPECT_FLOAT_EQ(float(points->values[7]), 0.8f);
    const auto* blackbody = std::get_if<BlackbodySpectrum>(&built.spectral.emission->shape);
    ASSERT_NE(blackbody, nullptr);
    EXPECT_EQ(blackbody->temperatureK, 2700);
    EXPECT_EQ(built.spectral.emission->scale, 4);
    const auto* preset = std::get_if<FluorophorePreset>(&*built.spectral.fluorescence);
    ASSERT_NE(preset, nullptr);
    EXPECT_EQ(preset->name, "fluorescein");

    // Absorption 1 across the visible under a reflectance of 0.8: refused, naming the material.
    Scene scene = verify::unitRoomScene(1, "D65", base);
    SessionSettings settings;
    settings.backend = "cpu";
    settings.subdivideMaxEdge = 0;
    settings.formFactors.progress = false;
    settings.logStages = false;
    auto session = Session::fromScene(std::move(scene), settings);
    ASSERT_TRUE(session) << session.error().message;
    MaterialDraft glowing = draftOf(session->scene().materials[0]);
    glowing.reflectanceRgb = {0.8f, 0.8f, 0.8f};
    glowing.fluorescenceKind = 3;
    glowing.absorptionPeakNm = 550;
    glowing.absorptionFwhmNm = 200;
    glowing.absorptionScale = 1;
    auto refused =
        session->setMaterial(0, materialFromDraft(session->scene().materials[0], glowing));
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("face0"), std::string::npos) << refused.error().message;
    glowing.absorptionScale = 0.1f;
    glowing.reflectanceRgb = {0.5f, 0.5f, 0.5f};
    ASSERT_TRUE(session->setMaterial(0, materialFromDraft(session->scene().materials[0], glowing)));
    EXPECT_EQ(session->fluorescentOperatorCount(), 1u);
}

// Undo takes back a whole gesture and redo restores it; a new gesture after an undo clears redo.
TEST(MaterialEdit, HistoryUndoesAndRedoesWholeGestures) {
    Material a;
    a.name = "a";
    Material b = a, c = a;
    a.baseColor = {0.1, 0.1, 0.1};
    b.baseColor = {0.5, 0.5, 0.5};
    c.baseColor = {0.9, 0.9, 0.9};
    std::vector<Material> state = {a, a};
    EditHistory history;
    EXPECT_FALSE(history.canUndo());
    history.record(0, state[0], draftOf(state[0]));  // a drag on material 0 ends at b
    state[0] = b;
    history.record(1, state[1], draftOf(state[1]));  // then material 1 to c
    state[1] = c;
    const auto current = [&](std::size_t index) {
        return EditHistory::Step{index, state[index], draftOf(state[index])};
    };
    const auto apply = [&](const std::optional<EditHistory::Step>& step) {
        ASSERT_TRUE(step);
        state[step->index] = step->material;
    };
    apply(history.undo(current));
    EXPECT_EQ(state[1].baseColor, a.baseColor);
    EXPECT_EQ(state[0].baseColor, b.baseColor);
    apply(history.undo(current));
    EXPECT_EQ(state[0].baseColor, a.baseColor);
    EXPECT_FALSE(history.canUndo());
    apply(history.redo(current));
    EXPECT_EQ(state[0].baseColor, b.baseColor);
    EXPECT_TRUE(history.canRedo());
    history.record(0, state[0], draftOf(state[0]));  // a new gesture: redo is gone
    EXPECT_FALSE(history.canRedo());
    EXPECT_FALSE(history.redo(current));
}

// The saved --materials JSON holds the edited materials only, overlays back to exactly the
// edited set, removes fluorescence with null, and refuses two same-named materials edited apart.
TEST(MaterialEdit, EditedMaterialsSaveAsAMaterialsFile) {
    Scene scene = verify::unitRoomScene(1, "D65");
    scene.materials[2].spectral.fluorescence = FluorophorePreset{"fluorescein"};
    std::vector<Material> current = scene.materials;
    current[0] = applyEdit(current[0], *parseMaterialEdit("face0.reflectance=rgb(0.2,0.6,0.9)"));
    current[2].spectral.fluorescence.reset();
    auto text = editedMaterialsJson(scene, current);
    ASSERT_TRUE(text) << text.error().message;
    const nlohmann::json saved = nlohmann::json::parse(*text);
    EXPECT_EQ(saved.size(), 2u) << *text;
    ASSERT_TRUE(saved.contains("face0"));
    EXPECT_EQ(saved["face0"]["reflectance"]["rgb"][1], 0.6);
    ASSERT_TRUE(saved.contains("face2"));
    EXPECT_TRUE(saved["face2"]["fluorescence"].is_null());
    for (std::size_t k : {std::size_t(0), std::size_t(2)}) {
        Material overlaid = scene.materials[k];
        auto extension = parseMaterialExtension(saved[current[k].name], "m.json");
        ASSERT_TRUE(extension) << extension.error().message;
        mergeExtension(overlaid.spectral, *extension);
        EXPECT_EQ(materialExtensionToJson(overlaid.spectral),
                  materialExtensionToJson(current[k].spectral));
    }
    scene.materials[3].name = current[3].name = "face0";
    current[3] = applyEdit(current[3], *parseMaterialEdit("face0.reflectance=rgb(0.5,0.5,0.5)"));
    EXPECT_FALSE(editedMaterialsJson(scene, current));
    EXPECT_TRUE(editedMaterialsJson(scene, scene.materials));  // nothing edited: {}
}

}  // namespace
}  // namespace daisy::viewer
#endif
