#pragma once
// Scripted material edits (`daisy view --edit`) and the editor panel's edits:
// `NAME.FIELD=VALUE`, where FIELD is a member of DAISY_materials_spectral (reflectance, emission
// or fluorescence) and VALUE is `rgb(r, g, b)` or that member's JSON (docs/scene_format.md), e.g.
//     Red.reflectance=rgb(0,1,0)
//     Lamp.emission={"blackbody": 2700, "scale": 5}
//     Paper.fluorescence={"preset": "fluorescein"}
// The value is checked by the scene loader's own parser (scene/material_extension.h); the physical
// check (reflectance + absorption <= 1) is Session::setMaterial's.
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/expected.h"
#include "scene/material.h"
#include "scene/scene.h"

namespace daisy::viewer {

struct MaterialEdit {
    std::string text;  // as given, for messages
    std::string materialName;
    MaterialExtension extension;  // the one member FIELD sets
};

// Parses `text`; errors quote it and say what is wrong.
Expected<MaterialEdit> parseMaterialEdit(const std::string& text);

// The indices of the scene's materials named edit.materialName (names may repeat); an error that
// lists the scene's names when there is none.
Expected<std::vector<std::size_t>> editTargets(const Scene& scene, const MaterialEdit& edit);

// `material` with the edit's member overlaid (scene/material.h mergeExtension).
Material applyEdit(Material material, const MaterialEdit& edit);

// The --materials JSON (docs/cli.md) that turns `initial` (the scene as loaded) into `current`
// (the same materials, edited): one entry per edited material, by name, with its spectral members
// ("fluorescence": null where an edit removed it). `daisy render SCENE --materials FILE` then
// solves with exactly the materials the viewer shows. Errors: two materials of one name edited
// differently (a --materials entry names every material of that name).
Expected<std::string> editedMaterialsJson(const Scene& initial,
                                          const std::vector<Material>& current);
// editedMaterialsJson written to `path` (core/atomic_file.h: whole or not at all).
Expected<void> saveEditedMaterials(const std::string& path, const Scene& initial,
                                   const std::vector<Material>& current);

// The editor's controls for one material.
struct MaterialDraft {
    std::array<float, 3> reflectanceRgb{0.8f, 0.8f, 0.8f};
    bool spectralReflectance = false;  // control points instead of RGB
    std::array<float, 8> reflectancePoints{};  // at kControlPointsNm
    int emissionKind = 0;  // 0 as loaded, 1 none, 2 preset, 3 blackbody
    int emissionPreset = 0;
    float blackbodyK = 3000;
    float emissionScale = 1;  // multiplies the preset, the blackbody or the emission as loaded
    int fluorescenceKind = 0;  // 0 as loaded, 1 none, 2 preset, 3 parameters
    int fluorescencePreset = 0;
    float absorptionPeakNm = 365, absorptionFwhmNm = 40, absorptionScale = 0.5f;
    float emissionPeakNm = 450, emissionFwhmNm = 50, quantumYield = 0.8f;
};

// The wavelengths of MaterialDraft::reflectancePoints, nm.
inline constexpr std::array<double, 8> kControlPointsNm = {350, 400, 450, 500, 550, 600, 650, 700};
// The names the draft's preset indices choose from.
inline constexpr std::array<const char*, 6> kEmissionPresets = {"D65", "D50", "A",
                                                                "F2",  "F11", "blacklight"};
inline constexpr std::array<const char*, 4> kFluorophorePresets = {"brightener", "fluorescein",
                                                                   "rhodamine6g", "neon"};

// The material `draft` describes over the scene's material `base`: the reflectance always (RGB or
// the control points, piecewise linear), emission and fluorescence unless "as loaded".
Material materialFromDraft(const Material& base, const MaterialDraft& draft);

// Undo and redo of material edits. One step is one gesture (a slider drag posts an edit per
// frame; undo goes back to before the drag): record() at a gesture's first change, with the
// material and draft before it.
class EditHistory {
public:
    struct Step {
        std::size_t index = 0;  // the material
        Material material;
        MaterialDraft draft;
    };
    // A new gesture on material `index` starts from `material` / `draft`; redo is cleared.
    void record(std::size_t index, Material material, MaterialDraft draft);
    // The step to apply to undo the last gesture, given what material `index` of that step is
    // now (`current` returns it), which redo will restore; nullopt when there is none.
    template <typename Current>
    std::optional<Step> undo(Current&& current) {
        return move(undo_, redo_, current);
    }
    template <typename Current>
    std::optional<Step> redo(Current&& current) {
        return move(redo_, undo_, current);
    }
    bool canUndo() const { return !undo_.empty(); }
    bool canRedo() const { return !redo_.empty(); }

private:
    template <typename Current>
    static std::optional<Step> move(std::vector<Step>& from, std::vector<Step>& to,
                                    Current& current) {
        if (from.empty()) return std::nullopt;
        Step step = std::move(from.back());
        from.pop_back();
        to.push_back(current(step.index));
        return step;
    }
    std::vector<Step> undo_, redo_;
};

// The panel's controls of one punctual light (KHR_lights_punctual): its intensity (cd, or lx
// for a directional light), its RGB colour, and its spectrum: as loaded (the file's spectral
// emission or the colour), an illuminant preset or a blackbody.
struct LightDraft {
    float intensity = 1;
    std::array<float, 3> color{1, 1, 1};
    int spectrumKind = 0;  // 0 as loaded, 1 preset, 2 blackbody
    int preset = 0;  // into kEmissionPresets
    float blackbodyK = 3000;
};
LightDraft lightDraftOf(const PunctualLight& light);
PunctualLight lightFromDraft(const PunctualLight& base, const LightDraft& draft);

// A draft showing `material` as loaded (its RGB or spectral RGB reflectance; the control points
// at the RGB's mean).
MaterialDraft draftOf(const Material& material);

}  // namespace daisy::viewer
