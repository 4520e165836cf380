#include "viewer/ui.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/strings.h"
#include "shared/viewer_types.h"
#include "spectral/wavelength_spec.h"
#include "viewer/material_edit.h"

namespace daisy::viewer {
namespace {

const char* const kWavelengthPresets[] = {"auto", "visible", "daisyriot", "meyer4", "fine"};

void statistics(const UiState& state, const DisplaySnapshot& snapshot, const SolveWorker& worker,
                const Scene& scene) {
    ImGui::Text("%s", scene.path.c_str());
    ImGui::Text("%zu patches from %zu triangles, %zu materials", worker.patches().patchCount(),
                scene.mesh.triangleCount(), scene.materials.size());
    ImGui::TextWrapped(
        "%zu wavelengths (%.0f..%.0f nm), %s transport: %s entries", snapshot.wavelengthCount,
        snapshot.wavelengthsNm.empty() ? 0.0 : snapshot.wavelengthsNm.front(),
        snapshot.wavelengthsNm.empty() ? 0.0 : snapshot.wavelengthsNm.back(),
        worker.transportKind(), formatCount(worker.transportStats().entries).c_str());
    ImGui::Text("frame %.2f ms, exposure %.2f EV", state.frameSeconds * 1e3, state.appliedEv);
}

void falseColourBar(const UiState& state, const DisplaySnapshot& snapshot) {
    const bool wavelength = state.display.quantity == DisplayQuantity::Wavelength;
    const double nm = wavelength && !snapshot.wavelengthsNm.empty()
        ? snapshot.wavelengthsNm[std::min(state.display.wavelengthIndex,
                                          snapshot.wavelengthsNm.size() - 1)]
        : 0;
    ImGui::Text(wavelength ? "L at %.1f nm (W m^-2 sr^-1 nm^-1), log scale"
                           : "luminance Y (normalised radiance), log scale",
                nm);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const float width = ImGui::GetContentRegionAvail().x, height = 14;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const int steps = 48;
    for (int k = 0; k < steps; ++k) {
        const shared::vec3 c = shared::falseColour((float(k) + 0.5f) / float(steps));
        draw->AddRectFilled(ImVec2(origin.x + width * float(k) / steps, origin.y),
                            ImVec2(origin.x + width * float(k + 1) / steps, origin.y + height),
                            ImGui::ColorConvertFloat4ToU32(ImVec4(c.x, c.y, c.z, 1)));
    }
    ImGui::Dummy(ImVec2(width, height));
    ImGui::Text("%.3g", std::pow(10.0, state.range.lo));
    ImGui::SameLine(std::max(width - 60, 80.0f));
    ImGui::Text("%.3g", std::pow(10.0, state.range.hi));
}

void viewControls(UiState& state, const DisplaySnapshot& snapshot, const Scene& scene) {
    int quantity = int(state.display.quantity);
    ImGui::RadioButton("colour", &quantity, 0);
    ImGui::SameLine();
    ImGui::RadioButton("luminance", &quantity, 1);
    ImGui::SameLine();
    ImGui::RadioButton("wavelength", &quantity, 2);
    state.display.quantity = DisplayQuantity(quantity);
    bool flat = !state.display.smooth;
    ImGui::Checkbox("flat", &flat);
    state.display.smooth = !flat;
    ImGui::SameLine();
    ImGui::Checkbox("wireframe", &state.wireframe);
    if (state.display.quantity == DisplayQuantity::Wavelength && snapshot.wavelengthCount > 0) {
        int index = int(std::min(state.display.wavelengthIndex, snapshot.wavelengthCount - 1));
        const std::string label =
            concat(formatNumber(snapshot.wavelengthsNm[std::size_t(index)], 4), " nm");
        ImGui::SliderInt("sample", &index, 0, int(snapshot.wavelengthCount) - 1, label.c_str());
        state.display.wavelengthIndex = std::size_t(index);
    }
    if (state.display.quantity != DisplayQuantity::Colour) {
        ImGui::Checkbox("automatic range", &state.display.autoRange);
        if (!state.display.autoRange) {
            float lo = float(state.display.falseLo), hi = float(state.display.falseHi);
            ImGui::DragFloatRange2("log10 range", &lo, &hi, 0.05f, -12, 6);
            state.display.falseLo = lo;
            state.display.falseHi = std::max(hi, lo + 0.01f);
        }
        falseColourBar(state, snapshot);
    } else {
        // Switching the automatic exposure off keeps the picture as it is: EV starts at the
        // exposure in use.
        if (ImGui::Checkbox("auto exposure", &state.autoExposure) && !state.autoExposure)
            state.ev = float(state.appliedEv);
        if (!state.autoExposure) ImGui::SliderFloat("EV", &state.ev, -12, 12, "%.2f");
    }
    ImGui::Checkbox("fly (WASD QE, drag to look)", &state.fly);
    if (ImGui::Button("reset view (R)")) state.cameraRequest = -2;
    ImGui::SameLine();
    if (ImGui::Button("frame all (Home)")) state.frameAllRequest = true;
    for (std::size_t k = 0; k < scene.cameras.size(); ++k) {
        ImGui::SameLine();
        const std::string name =
            scene.cameras[k].name.empty() ? concat("camera ", k) : scene.cameras[k].name;
        if (ImGui::Button(name.c_str())) state.cameraRequest = int(k);
    }
    if (ImGui::Button("screenshot (F12)")) state.screenshotRequest = true;
}

void solverControls(UiState& state, const DisplaySnapshot& snapshot, SolveWorker& worker) {
    if (ImGui::Button("one bounce")) worker.stepBounce();
    ImGui::SameLine();
    if (ImGui::Button("to convergence")) worker.converge();
    ImGui::SameLine();
    if (ImGui::Button("reset to emission")) worker.resetToEmission();
    ImGui::Text("%s: iteration %d, change %.3g", snapshot.solving ? "solving" : "idle",
                snapshot.iteration, snapshot.change);
    if (snapshot.residual >= 0) {
        ImGui::Text("residual %.3g%s", snapshot.residual, snapshot.converged ? " (converged)" : "");
    }
    char text[128];
    std::snprintf(text, sizeof text, "%s", state.wavelengthsText.c_str());
    if (ImGui::BeginCombo("##preset", nullptr, ImGuiComboFlags_NoPreview)) {
        for (const char* preset : kWavelengthPresets) {
            if (ImGui::Selectable(preset)) std::snprintf(text, sizeof text, "%s", preset);
        }
        ImGui::EndCombo();
    }
    ImGui::SameLine();
    ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.6f);
    ImGui::InputText("wavelengths", text, sizeof text);
    state.wavelengthsText = text;
    if (ImGui::Button("apply wavelengths")) {
        auto spec = parseWavelengthSpec(state.wavelengthsText);
        if (spec) {
            worker.setWavelengths(*spec, state.wavelengthsText);
        } else {
            state.wavelengthsText += "  <- " + spec.error().message;
        }
    }
}

// The editor of one material; true when a control changed.
// `loadedEmits`: the material as loaded emits light; `watts` and `lumens` what it emits now.
bool materialEditor(MaterialDraft& draft, bool loadedEmits, double watts, double lumens) {
    bool changed = false;
    changed |= ImGui::Checkbox("spectral reflectance", &draft.spectralReflectance);
    if (draft.spectralReflectance) {
        for (int k = 0; k < 8; ++k) {
            if (k > 0) ImGui::SameLine();
            ImGui::PushID(k);
            changed |= ImGui::VSliderFloat("##rho", ImVec2(22, 90),
                                           &draft.reflectancePoints[std::size_t(k)], 0, 1, "");
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("%.0f nm: %.3f", kControlPointsNm[std::size_t(k)],
                                  draft.reflectancePoints[std::size_t(k)]);
            ImGui::PopID();
        }
        ImGui::PlotLines("rho(350..700 nm)", draft.reflectancePoints.data(), 8, 0, nullptr, 0, 1,
                         ImVec2(0, 40));
    } else {
        changed |= ImGui::ColorEdit3("reflectance", draft.reflectanceRgb.data());
    }
    const char* emissionKinds[] = {"as loaded", "none", "preset", "blackbody"};
    changed |= ImGui::Combo("emission", &draft.emissionKind, emissionKinds, 4);
    if (draft.emissionKind == 2)
        changed |= ImGui::Combo("illuminant", &draft.emissionPreset, kEmissionPresets.data(),
                                int(kEmissionPresets.size()));
    if (draft.emissionKind == 3)
        changed |= ImGui::SliderFloat("temperature K", &draft.blackbodyK, 1000, 12000, "%.0f");
    // "as loaded" keeps the file's emission spectrum; its scale multiplies it.
    if (draft.emissionKind >= 2 || (draft.emissionKind == 0 && loadedEmits))
        changed |= ImGui::SliderFloat("scale", &draft.emissionScale, 0, 100, "%.2f",
                                      ImGuiSliderFlags_Logarithmic);
    if (watts > 0) {
        ImGui::TextDisabled("emits %s W, %s lm", formatNumber(watts, 4).c_str(),
                            formatNumber(lumens, 4).c_str());
    }
    const char* fluorescenceKinds[] = {"as loaded", "none", "preset", "parameters"};
    changed |= ImGui::Combo("fluorescence", &draft.fluorescenceKind, fluorescenceKinds, 4);
    if (draft.fluorescenceKind == 2)
        changed |= ImGui::Combo("fluorophore", &draft.fluorescencePreset,
                                kFluorophorePresets.data(), int(kFluorophorePresets.size()));
    if (draft.fluorescenceKind == 3) {
        changed |= ImGui::SliderFloat("absorption peak nm", &draft.absorptionPeakNm, 300, 700);
        changed |= ImGui::SliderFloat("absorption FWHM nm", &draft.absorptionFwhmNm, 5, 200);
        changed |= ImGui::SliderFloat("absorption", &draft.absorptionScale, 0, 1);
        changed |= ImGui::SliderFloat("emission peak nm", &draft.emissionPeakNm, 350, 750);
        changed |= ImGui::SliderFloat("emission FWHM nm", &draft.emissionFwhmNm, 5, 200);
        changed |= ImGui::SliderFloat("quantum yield", &draft.quantumYield, 0, 1);
    }
    return changed;
}

// B and G of the picked patch on one chart: wavelength in nm along x (ticks every 50 or 100
// nm), one linear y scale for both from 0 to their peak, a legend, and under the mouse a vertical
// line with the nearest sample's values.
void spectralChart(const std::vector<double>& nm, const std::vector<float>& radiosity,
                   const std::vector<float>& incident) {
    const std::size_t m = nm.size();
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const float width = std::max(ImGui::GetContentRegionAvail().x, 120.0f), height = 150;
    const float left = 42, bottom = 18, right = 6, top = 6;
    const ImVec2 plotLow(origin.x + left, origin.y + top);
    const ImVec2 plotHigh(origin.x + width - right, origin.y + height - bottom);
    ImGui::InvisibleButton("chart", ImVec2(width, height));
    const bool hovered = ImGui::IsItemHovered();
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImU32 axis = ImGui::GetColorU32(ImGuiCol_TextDisabled);
    const ImU32 text = ImGui::GetColorU32(ImGuiCol_Text);
    const ImU32 colourB = IM_COL32(255, 170, 60, 255), colourG = IM_COL32(90, 170, 255, 255);
    draw->AddRect(plotLow, plotHigh, axis);
    const double lo = nm.front(), hi = nm.back() > lo ? nm.back() : lo + 1;
    float peak = 0;
    for (std::size_t k = 0; k < m; ++k)
        peak = std::max({peak, radiosity[k], incident[k]});
    const float yTop = peak > 0 ? peak * 1.05f : 1.0f;
    const auto x = [&](double lambda) {
        return plotLow.x + float((lambda - lo) / (hi - lo)) * (plotHigh.x - plotLow.x);
    };
    const auto y = [&](float value) {
        return plotHigh.y - value / yTop * (plotHigh.y - plotLow.y);
    };
    const double step = hi - lo > 250 ? 100 : 50;
    for (double tick = std::ceil(lo / step) * step; tick <= hi + 1e-9; tick += step) {
        draw->AddLine(ImVec2(x(tick), plotHigh.y), ImVec2(x(tick), plotHigh.y + 3), axis);
        const std::string label = formatNumber(tick, 4);
        draw->AddText(ImVec2(x(tick) - 10, plotHigh.y + 3), text, label.c_str());
    }
    const std::string topLabel = concat(formatNumber(double(yTop), 2));
    draw->AddText(ImVec2(origin.x, plotLow.y), text, topLabel.c_str());
    draw->AddText(ImVec2(origin.x + 8, plotHigh.y - 14), text, "0");
    for (std::size_t k = 0; k + 1 < m; ++k) {
        draw->AddLine(ImVec2(x(nm[k]), y(incident[k])), ImVec2(x(nm[k + 1]), y(incident[k + 1])),
                      colourG, 1.5f);
        draw->AddLine(ImVec2(x(nm[k]), y(radiosity[k])), ImVec2(x(nm[k + 1]), y(radiosity[k + 1])),
                      colourB, 2.0f);
    }
    for (std::size_t k = 0; k < m; ++k)
        draw->AddCircleFilled(ImVec2(x(nm[k]), y(radiosity[k])), 2.0f, colourB);
    // Legend, top right.
    const float legendX = plotHigh.x - 120;
    draw->AddLine(ImVec2(legendX, plotLow.y + 8), ImVec2(legendX + 14, plotLow.y + 8), colourB, 2);
    draw->AddText(ImVec2(legendX + 18, plotLow.y + 1), text, "B (radiosity)");
    draw->AddLine(ImVec2(legendX, plotLow.y + 22), ImVec2(legendX + 14, plotLow.y + 22), colourG,
                  2);
    draw->AddText(ImVec2(legendX + 18, plotLow.y + 15), text, "G (incident)");
    if (hovered) {
        const float mouse = ImGui::GetIO().MousePos.x;
        std::size_t nearest = 0;
        for (std::size_t k = 1; k < m; ++k)
            if (std::abs(x(nm[k]) - mouse) < std::abs(x(nm[nearest]) - mouse)) nearest = k;
        draw->AddLine(ImVec2(x(nm[nearest]), plotLow.y), ImVec2(x(nm[nearest]), plotHigh.y), text);
        ImGui::SetTooltip("%.1f nm\nB %.4g W m^-2 nm^-1\nG %.4g W m^-2 nm^-1", nm[nearest],
                          double(radiosity[nearest]), double(incident[nearest]));
    }
    ImGui::TextDisabled("wavelength (nm); W m^-2 nm^-1");
}

// The file's punctual lights: intensity, colour and spectrum; an edit recomputes their direct
// light (Session::setLight) and re-solves.
void lightControls(UiState& state, const DisplaySnapshot& snapshot, SolveWorker& worker,
                   const Scene& scene) {
    for (std::size_t k = 0; k < scene.lights.size() && k < state.lightDrafts.size(); ++k) {
        const PunctualLight& light = scene.lights[k];
        const bool directional = light.type == PunctualLight::Type::Directional;
        ImGui::PushID(int(1000 + k));
        const std::string label =
            concat(light.name,
                   directional                                   ? " (directional)"
                       : light.type == PunctualLight::Type::Spot ? " (spot)"
                                                                 : " (point)");
        if (ImGui::TreeNode(label.c_str())) {
            LightDraft& draft = state.lightDrafts[k];
            bool changed =
                ImGui::SliderFloat(directional ? "intensity lx" : "intensity cd", &draft.intensity,
                                   0, 1e5f, "%.3g", ImGuiSliderFlags_Logarithmic);
            changed |= ImGui::ColorEdit3("colour", draft.color.data());
            const char* kinds[] = {"as loaded", "preset", "blackbody"};
            changed |= ImGui::Combo("spectrum", &draft.spectrumKind, kinds, 3);
            if (draft.spectrumKind == 1)
                changed |= ImGui::Combo("illuminant", &draft.preset, kEmissionPresets.data(),
                                        int(kEmissionPresets.size()));
            if (draft.spectrumKind == 2)
                changed |=
                    ImGui::SliderFloat("temperature K", &draft.blackbodyK, 1000, 12000, "%.0f");
            if (changed) worker.setLight(k, lightFromDraft(light, draft));
            if (k < snapshot.lights.size())
                ImGui::TextDisabled("%s %s", formatNumber(snapshot.lights[k].intensity, 4).c_str(),
                                    directional ? "lx" : "cd");
            ImGui::TreePop();
        }
        ImGui::PopID();
    }
}

// Undo / redo buttons (and the viewer's Ctrl+Z / Ctrl+Y requests): a step restores a
// material and its controls as they were before (or after) one gesture.
void editHistoryControls(UiState& state, SolveWorker& worker) {
    ImGui::BeginDisabled(!state.history.canUndo());
    state.undoRequest |= ImGui::Button("undo (Ctrl+Z)");
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::BeginDisabled(!state.history.canRedo());
    state.redoRequest |= ImGui::Button("redo (Ctrl+Y)");
    ImGui::EndDisabled();
    const auto current = [&](std::size_t index) {
        return EditHistory::Step{index, state.requested[index], state.drafts[index]};
    };
    std::optional<EditHistory::Step> step;
    if (state.undoRequest) step = state.history.undo(current);
    if (state.redoRequest) step = state.history.redo(current);
    state.undoRequest = state.redoRequest = false;
    if (!step || step->index >= state.requested.size()) return;
    state.requested[step->index] = step->material;
    state.drafts[step->index] = step->draft;
    worker.setMaterial(step->index, step->material);
}

// "save materials": the session's materials, as edited, as a --materials file.
void saveControls(UiState& state, const DisplaySnapshot& snapshot, const SolveWorker& worker) {
    char path[512];
    std::snprintf(path, sizeof path, "%s", state.materialsPath.c_str());
    if (ImGui::Button("save materials")) {
        auto saved =
            saveEditedMaterials(state.materialsPath, worker.initialScene(), snapshot.materials);
        state.savedMessage = saved
            ? concat("wrote ", state.materialsPath, " (daisy render ", worker.initialScene().path,
                     " --materials ", state.materialsPath, ")")
            : saved.error().message;
    }
    ImGui::SameLine();
    ImGui::SetNextItemWidth(-1);
    if (ImGui::InputText("##materials path", path, sizeof path)) state.materialsPath = path;
    if (!state.savedMessage.empty()) ImGui::TextWrapped("%s", state.savedMessage.c_str());
}

void pickedPatch(const UiState& state, const DisplaySnapshot& snapshot, const Scene& scene,
                 const SolveWorker& worker) {
    if (!state.picked) {
        ImGui::TextDisabled("click a surface to plot its B(lambda)");
        return;
    }
    const std::size_t p = *state.picked, m = snapshot.wavelengthCount;
    if (m == 0 || (p + 1) * m > snapshot.radiosity.size()) return;
    std::vector<float> radiosity(m), incident(m);
    const bool haveG = snapshot.gathered.size() == worker.patches().patchCount() * m;
    for (std::size_t k = 0; k < m; ++k) {
        radiosity[k] = float(snapshot.radiosity[p * m + k]);
        incident[k] = haveG ? float(snapshot.gathered[p * m + k]) : 0.0f;
    }
    const uint32_t material = worker.patches().materials[p];
    ImGui::Text("patch %zu, material '%s'", p,
                material < scene.materials.size() ? scene.materials[material].name.c_str() : "");
    spectralChart(snapshot.wavelengthsNm, radiosity, incident);
    if (!haveG) ImGui::TextDisabled("G appears when a solve finishes");
}

}  // namespace

void initUi(UiState& state, const Scene& scene, const std::string& wavelengthsText,
            const std::string& materialsPath) {
    state.wavelengthsText = wavelengthsText;
    state.drafts.clear();
    for (const Material& material : scene.materials)
        state.drafts.push_back(draftOf(material));
    state.requested = scene.materials;
    state.lightDrafts.clear();
    for (const PunctualLight& light : scene.lights)
        state.lightDrafts.push_back(lightDraftOf(light));
    state.materialsPath = materialsPath;
}

void drawPanel(UiState& state, const DisplaySnapshot& snapshot, SolveWorker& worker,
               const Scene& scene) {
    // Docked at the left, full height; the picture is framed in the rest of the window. Folded
    // to its title bar (the arrow), it gives the picture the whole window.
    const ImVec2 window = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(0, 0), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(std::min(kPanelWidth, window.x / 2), window.y),
                             ImGuiCond_Always);
    const bool open =
        ImGui::Begin("DaisyRiot", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize);
    state.panelCollapsed = !open;
    if (!open) {
        ImGui::End();
        return;
    }
    statistics(state, snapshot, worker, scene);
    if (ImGui::CollapsingHeader("view", ImGuiTreeNodeFlags_DefaultOpen))
        viewControls(state, snapshot, scene);
    if (ImGui::CollapsingHeader("solver", ImGuiTreeNodeFlags_DefaultOpen))
        solverControls(state, snapshot, worker);
    if (ImGui::CollapsingHeader("materials")) {
        if (!snapshot.message.empty()) {
            ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.4f, 0.3f, 1));
            ImGui::TextWrapped("%s", snapshot.message.c_str());
            ImGui::PopStyleColor();
        }
        // A refused edit leaves the session's material in use: its draft goes back to it, so
        // the next drag starts from what is shown, not from the refused value.
        if (snapshot.refusedEdits > state.refusalsSeen) {
            state.refusalsSeen = snapshot.refusedEdits;
            const std::size_t refused = snapshot.refusedMaterial;
            if (refused < state.drafts.size() && refused < snapshot.materials.size()) {
                state.drafts[refused] = draftOf(snapshot.materials[refused]);
                state.requested[refused] = snapshot.materials[refused];
            }
        }
        editHistoryControls(state, worker);
        saveControls(state, snapshot, worker);
        for (std::size_t k = 0; k < state.drafts.size() && k < scene.materials.size(); ++k) {
            ImGui::PushID(int(k));
            if (ImGui::TreeNode(scene.materials[k].name.c_str())) {
                const MaterialDraft before = state.drafts[k];
                const double watts =
                    k < snapshot.emittedWatts.size() ? snapshot.emittedWatts[k] : 0.0;
                const double lumens =
                    k < snapshot.emittedLumens.size() ? snapshot.emittedLumens[k] : 0.0;
                if (materialEditor(state.drafts[k], scene.materials[k].isEmissive(), watts,
                                   lumens)) {
                    if (!state.gesture) state.history.record(k, state.requested[k], before);
                    state.gesture = true;
                    state.requested[k] = materialFromDraft(scene.materials[k], state.drafts[k]);
                    worker.setMaterial(k, state.requested[k]);
                }
                ImGui::TreePop();
            }
            ImGui::PopID();
        }
        if (!ImGui::IsAnyItemActive()) state.gesture = false;
    }
    if (!scene.lights.empty() && ImGui::CollapsingHeader("lights"))
        lightControls(state, snapshot, worker, scene);
    if (ImGui::CollapsingHeader("picked patch", ImGuiTreeNodeFlags_DefaultOpen))
        pickedPatch(state, snapshot, scene, worker);
    ImGui::End();
}

}  // namespace daisy::viewer
