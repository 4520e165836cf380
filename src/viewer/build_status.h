#pragma once
// What the window says while F is being made (viewer/solve_worker.h BuildProgress): a line for
// the title and the log ("view factors 42%, about 12 s left"), and a small Dear ImGui window
// with a progress bar over the picture, shown whether or not the panel is.
#include <string>

#include "viewer/solve_worker.h"

namespace daisy::viewer {

// "view factors 42%, about 12 s left" (the ETA once known); "" when F is not being made. A
// failed build: "no view factors: <reason>".
std::string buildStatusLine(const BuildProgress& progress, const DisplaySnapshot& snapshot);

// Draws the progress window (between ImGui::NewFrame and ImGui::Render) while F is being made
// or when it failed; nothing otherwise.
void drawBuildStatus(const BuildProgress& progress, const DisplaySnapshot& snapshot);

}  // namespace daisy::viewer
