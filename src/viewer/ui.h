#pragma once
// The viewer's Dear ImGui panel: scene statistics, view modes and exposure,
// cameras, solver controls (one bounce, to convergence, reset to emission; iteration, change and
// residual live), the wavelength set, the materials editor, and the picked patch's B(lambda) and
// incident light. Edits go to the solve worker, which refuses invalid ones with the reason shown.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "viewer/display_values.h"
#include "viewer/material_edit.h"
#include "viewer/solve_worker.h"

namespace daisy::viewer {

struct UiState {
    DisplaySettings display;
    bool wireframe = false;
    bool autoExposure = true;
    float ev = 0;  // fixed exposure, stops
    bool fly = false;  // fly controls instead of orbit
    int cameraRequest = -1;  // set by the panel: a glTF camera to switch to; -2 = reset view
    std::optional<uint32_t> picked;  // the clicked patch
    std::string wavelengthsText = "auto";
    double frameSeconds = 0;  // measured by the loop
    double appliedEv = 0;  // the exposure in use, stops
    FalseRange range;  // of the false colour in use
    std::vector<MaterialDraft> drafts;  // per material; filled by initUi
    std::vector<Material> requested;  // per material: what the panel last asked the worker for
    std::vector<LightDraft> lightDrafts;  // per punctual light
    EditHistory history;
    bool gesture = false;  // an edit gesture (a drag) is under way: one undo step
    bool undoRequest = false, redoRequest = false;  // Ctrl+Z, Ctrl+Y (set by the viewer)
    std::string materialsPath;  // "save materials" writes here
    std::string savedMessage;  // the last save's outcome
    bool panelCollapsed = false;  // the docked panel folded to its title bar
    bool frameAllRequest = false;  // "frame all": the whole scene in view
    int refusalsSeen = 0;  // DisplaySnapshot::refusedEdits already reverted in the drafts
    bool screenshotRequest = false;
};

// The docked panel's width in pixels (at most half the window); the picture fills the rest.
inline constexpr float kPanelWidth = 400;

// Fills the drafts from the scene's materials; "save materials" defaults to `materialsPath`.
void initUi(UiState& state, const Scene& scene, const std::string& wavelengthsText,
            const std::string& materialsPath);

// Draws the panel (between ImGui::NewFrame and ImGui::Render) and posts edits to `worker`.
void drawPanel(UiState& state, const DisplaySnapshot& snapshot, SolveWorker& worker,
               const Scene& scene);

}  // namespace daisy::viewer
