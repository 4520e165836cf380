#pragma once
// `daisy view` (docs/viewer.md): a GLFW window with a Vulkan swapchain that shows the
// session's smooth vertex radiance rasterised (the picture `daisy render` ray-casts), a camera to
// orbit and fly, and a Dear ImGui panel with the solver controls and a live materials editor
// whose re-solves run in the background (viewer/solve_worker.h). The test mode (--frames N,
// --screenshot FILE) draws N frames without the panel, waits for the solves it started, saves the
// last frame's pixels as a PNG and exits.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/timer.h"
#include "image/exposure.h"
#include "pipeline/session.h"

namespace daisy::viewer {

struct ViewerOptions {
    std::string device;  // --device: index or part of the name; empty = by type
    std::string camera;  // --camera: glTF camera name or index; empty = first, or framing
    int width = 1280;  // the window's framebuffer size at start, pixels
    int height = 720;
    Exposure exposure;  // --exposure
    int frames = 0;  // > 0: draw at least this many frames, then exit (the test mode)
    std::string screenshotPath;  // the test mode's PNG of the last frame; F12 writes one too
    // The edited materials as a --materials file: written at the test mode's last frame, and
    // the panel's "save materials" default (else SCENE_STEM.materials.json).
    std::string saveMaterialsPath;
    std::vector<std::string> edits;  // --edit NAME.FIELD=VALUE, applied after the first frame
    bool exerciseWindow = false;  // --exercise-window: resize and minimise during the frames
    bool panel = false;  // --panel: show the panel in the test mode too
    // --pick X,Y: pick the patch under framebuffer pixel (X, Y) as a click there would (logged)
    std::optional<std::array<double, 2>> pick;
    std::string display;  // --display (viewer/display_values.h parseDisplay); empty = colour
    std::string wavelengthsText = "auto";  // --wavelengths as typed, for the panel
    // When the command started: the log's times of the first frame and the first converged one.
    Clock::time_point startedAt = Clock::now();
};

// Why the viewer cannot run here, checked before the view factors so that it fails in
// milliseconds: GLFW cannot reach a display, there is no Vulkan loader or driver, or no device
// with graphics matches `device` (--device). `status` is 2 for a --device that names no usable
// device (a bad option), 1 for what the machine lacks; "" and 0 when the viewer can start.
struct ViewerUnavailable {
    std::string why;
    int status = 0;
};
ViewerUnavailable viewerUnavailable(const std::string& device);

// Runs the viewer on `session` (patches, E and M ready; F and the solution are made by the solve
// worker while the window shows the emission) until the window closes, or for the test mode's
// frames, and returns the exit status: 0, 2 for a bad --edit or --camera (checked before the
// window opens), for view factors that could not be made (the test mode) and for a failed Vulkan
// call (VK_CHECK's message: out of device memory, a lost device or surface), 1 for no display or
// no Vulkan device that presents (the message, logged, says which).
int runViewer(Session session, const ViewerOptions& options);

}  // namespace daisy::viewer
