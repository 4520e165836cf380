#include "viewer/material_edit.h"

#include <algorithm>
#include <cstdio>
#include <variant>

#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/strings.h"
#include "scene/bounded_json.h"
#include "scene/material_extension.h"

namespace daisy::viewer {
namespace {

std::string trim(const std::string& text) {
    const std::size_t first = text.find_first_not_of(" \t");
    if (first == std::string::npos) return "";
    return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

// `rgb(r, g, b)` as the JSON {"rgb": [r, g, b]}; the text unchanged when it is not of that form.
std::string expandRgb(const std::string& value) {
    if (value.rfind("rgb(", 0) != 0 || value.back() != ')') return value;
    return concat("{\"rgb\": [", value.substr(4, value.size() - 5), "]}");
}

}  // namespace

Expected<MaterialEdit> parseMaterialEdit(const std::string& text) {
    const std::string usage = concat("--edit '", text,
                                     "': expected NAME.FIELD=VALUE with FIELD reflectance, "
                                     "emission or fluorescence");
    const std::size_t equals = text.find('=');
    if (equals == std::string::npos) return Error{usage};
    const std::string left = trim(text.substr(0, equals));
    const std::string value = trim(text.substr(equals + 1));
    const std::size_t dot = left.rfind('.');
    if (dot == std::string::npos || dot == 0 || value.empty()) return Error{usage};
    MaterialEdit edit;
    edit.text = text;
    edit.materialName = left.substr(0, dot);
    const std::string field = left.substr(dot + 1);
    if (field != "reflectance" && field != "emission" && field != "fluorescence") {
        return Error{concat(usage, " (got '", field, "')")};
    }
    auto member = parseBoundedJson(expandRgb(value));
    if (!member) return Error{concat("--edit '", text, "': ", member.error().message)};
    nlohmann::json object = nlohmann::json::object();
    object[field] = *member;
    auto extension = parseMaterialExtension(object, concat("--edit ", edit.materialName));
    if (!extension) return Error{concat("--edit '", text, "': ", extension.error().message)};
    edit.extension = std::move(*extension);
    return edit;
}

Expected<std::vector<std::size_t>> editTargets(const Scene& scene, const MaterialEdit& edit) {
    std::vector<std::size_t> targets;
    std::string names;
    for (std::size_t k = 0; k < scene.materials.size(); ++k) {
        if (scene.materials[k].name == edit.materialName) targets.push_back(k);
        if (names.find(concat("'", scene.materials[k].name, "'")) == std::string::npos)
            names += concat(names.empty() ? "" : ", ", "'", scene.materials[k].name, "'");
    }
    if (targets.empty()) {
        return Error{concat("--edit '", edit.text, "': ", scene.path, " has no material '",
                            edit.materialName, "' (it has ", names.empty() ? "none" : names, ")")};
    }
    return targets;
}

Material applyEdit(Material material, const MaterialEdit& edit) {
    mergeExtension(material.spectral, edit.extension);
    return material;
}

Expected<std::string> editedMaterialsJson(const Scene& initial,
                                          const std::vector<Material>& current) {
    nlohmann::json out = nlohmann::json::object();
    for (std::size_t k = 0; k < current.size() && k < initial.materials.size(); ++k) {
        const Material& before = initial.materials[k];
        const Material& after = current[k];
        bool representable = true;
        nlohmann::json entry = materialExtensionToJson(after.spectral, &representable);
        if (before.spectral.fluorescence && !after.spectral.fluorescence) {
            entry["fluorescence"] = nullptr;
        }
        if (entry == materialExtensionToJson(before.spectral)) continue;  // not edited
        if (!representable) entry.erase("fluorescence");  // unchanged MTL Ks colour
        if (const auto found = out.find(after.name); found != out.end() && *found != entry) {
            return Error{concat("materials named '", after.name,
                                "' were edited differently; a --materials entry names every "
                                "material of that name, so the edits cannot be saved")};
        }
        out[after.name] = std::move(entry);
    }
    // One line per material, so the file reads and diffs by material.
    std::string text = "{";
    for (auto it = out.begin(); it != out.end(); ++it)
        text += concat(it == out.begin() ? "\n  " : ",\n  ", nlohmann::json(it.key()).dump(), ": ",
                       it.value().dump());
    return text + "\n}\n";
}

Expected<void> saveEditedMaterials(const std::string& path, const Scene& initial,
                                   const std::vector<Material>& current) {
    auto text = editedMaterialsJson(initial, current);
    if (!text) return withContext(text.error(), path);
    return writeFileAtomically(path, [&](std::FILE* file) {
        std::fwrite(text->data(), 1, text->size(), file);
        return std::string();
    });
}

Material materialFromDraft(const Material& base, const MaterialDraft& draft) {
    Material material = base;
    if (draft.spectralReflectance) {
        TabulatedSpectrum points;
        for (std::size_t k = 0; k < kControlPointsNm.size(); ++k) {
            points.wavelengthsNm.push_back(kControlPointsNm[k]);
            points.values.push_back(draft.reflectancePoints[k]);
        }
        material.spectral.reflectance = SpectrumSpec{points, 1.0};
    } else {
        RgbSpectrum rgb;
        for (std::size_t c = 0; c < 3; ++c)
            rgb.rgb[c] = draft.reflectanceRgb[c];
        material.spectral.reflectance = SpectrumSpec{rgb, 1.0};
    }
    const auto pick = [](const auto& names, int index) {
        return names[std::size_t(std::clamp(index, 0, int(names.size()) - 1))];
    };
    switch (draft.emissionKind) {
        case 1:
            material.spectral.emission = SpectrumSpec{RgbSpectrum{}, 0.0};
            material.emissiveRgb = {0, 0, 0};
            break;
        case 2:
            material.spectral.emission = SpectrumSpec{
                PresetSpectrum{pick(kEmissionPresets, draft.emissionPreset)}, draft.emissionScale};
            break;
        case 3:
            material.spectral.emission =
                SpectrumSpec{BlackbodySpectrum{draft.blackbodyK}, draft.emissionScale};
            break;
        default:
            // As loaded: the file's spectrum (or RGB emission), times the scale.
            if (draft.emissionScale != 1) {
                if (material.spectral.emission) {
                    material.spectral.emission->scale *= draft.emissionScale;
                } else if (material.emissiveRgb != std::array<double, 3>{0, 0, 0}) {
                    // The RGB emission as the spectral member it stands for, so that a saved
                    // --materials file carries the scale.
                    material.spectral.emission =
                        SpectrumSpec{RgbSpectrum{material.emissiveRgb}, draft.emissionScale};
                }
            }
            break;
    }
    switch (draft.fluorescenceKind) {
        case 1:
            material.spectral.fluorescence.reset();
            break;
        case 2:
            material.spectral.fluorescence =
                FluorophorePreset{pick(kFluorophorePresets, draft.fluorescencePreset)};
            break;
        case 3: {
            FluorescenceParams params;
            params.absorption =
                SpectrumSpec{GaussianSpectrum{draft.absorptionPeakNm, draft.absorptionFwhmNm},
                             draft.absorptionScale};
            params.emission =
                SpectrumSpec{GaussianSpectrum{draft.emissionPeakNm, draft.emissionFwhmNm}, 1.0};
            params.quantumYield = draft.quantumYield;
            material.spectral.fluorescence = params;
            break;
        }
        default:
            break;
    }
    return material;
}

LightDraft lightDraftOf(const PunctualLight& light) {
    LightDraft draft;
    draft.intensity = float(light.intensity);
    for (std::size_t c = 0; c < 3; ++c)
        draft.color[c] = float(light.color[c]);
    return draft;
}

PunctualLight lightFromDraft(const PunctualLight& base, const LightDraft& draft) {
    PunctualLight light = base;
    light.intensity = draft.intensity;
    for (std::size_t c = 0; c < 3; ++c)
        light.color[c] = draft.color[c];
    if (draft.spectrumKind == 1) {
        const std::size_t preset =
            std::size_t(std::clamp(draft.preset, 0, int(kEmissionPresets.size()) - 1));
        light.spectrum = SpectrumSpec{PresetSpectrum{kEmissionPresets[preset]}, 1.0};
    } else if (draft.spectrumKind == 2) {
        light.spectrum = SpectrumSpec{BlackbodySpectrum{draft.blackbodyK}, 1.0};
    }
    return light;
}

void EditHistory::record(std::size_t index, Material material, MaterialDraft draft) {
    undo_.push_back({index, std::move(material), draft});
    redo_.clear();
}

MaterialDraft draftOf(const Material& material) {
    MaterialDraft draft;
    for (std::size_t c = 0; c < 3; ++c)
        draft.reflectanceRgb[c] = float(material.baseColor[c]);
    if (material.spectral.reflectance) {
        if (const auto* rgb = std::get_if<RgbSpectrum>(&material.spectral.reflectance->shape)) {
            for (std::size_t c = 0; c < 3; ++c)
                draft.reflectanceRgb[c] = float(rgb->rgb[c]);
        }
    }
    const float mean =
        (draft.reflectanceRgb[0] + draft.reflectanceRgb[1] + draft.reflectanceRgb[2]) / 3;
    draft.reflectancePoints.fill(mean);
    return draft;
}

}  // namespace daisy::viewer
