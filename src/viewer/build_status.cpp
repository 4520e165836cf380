#include "viewer/build_status.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

#include "core/progress.h"
#include "core/strings.h"

namespace daisy::viewer {

std::string buildStatusLine(const BuildProgress& progress, const DisplaySnapshot& snapshot) {
    if (!snapshot.error.empty()) return concat("no view factors: ", snapshot.error);
    if (!progress.active) return {};
    std::string line = concat(progress.stage, " ", int(std::floor(progress.fraction * 100)), "%");
    if (progress.etaSeconds >= 0)
        line += concat(", about ", formatDuration(progress.etaSeconds), " left");
    return line;
}

void drawBuildStatus(const BuildProgress& progress, const DisplaySnapshot& snapshot) {
    if (!progress.active && snapshot.error.empty()) return;
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    const float width = std::min(460.0f, viewport->Size.x - 20);
    // Centred at the bottom, clear of the panel at the left.
    ImGui::SetNextWindowPos(
        ImVec2(viewport->Pos.x + viewport->Size.x * 0.5f, viewport->Pos.y + viewport->Size.y - 12),
        ImGuiCond_Always, ImVec2(0.5f, 1.0f));
    ImGui::SetNextWindowSize(ImVec2(width, 0));
    ImGui::SetNextWindowBgAlpha(0.8f);
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove |
        ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
        ImGuiWindowFlags_NoNav;
    if (ImGui::Begin("##build", nullptr, flags)) {
        if (!snapshot.error.empty()) {
            ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.4f, 0.4f, 1));
            ImGui::TextWrapped("No view factors, nothing can be solved: %s",
                               snapshot.error.c_str());
            ImGui::PopStyleColor();
        } else {
            ImGui::TextUnformatted(
                !snapshot.building         ? "Edit solved; refining the links where it moved light"
                    : snapshot.fromCache   ? "Converged solution from the cache; making the view "
                                             "factors for edits"
                    : snapshot.directLight ? "Direct light shown; making the view factors"
                                           : "Emission shown; making the view factors");
            const std::string label = buildStatusLine(progress, snapshot);
            ImGui::ProgressBar(float(progress.fraction), ImVec2(-1, 0), label.c_str());
            ImGui::Text("%s elapsed", formatDuration(progress.elapsedSeconds).c_str());
        }
    }
    ImGui::End();
}

}  // namespace daisy::viewer
