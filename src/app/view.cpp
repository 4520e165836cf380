// `daisy view SCENE` (docs/viewer.md): the checks of the options and the machine, the session
// (scene, automatic patch size, E and M), then the viewer (src/viewer/), which opens its window
// at once and makes F (cache or backend) and the solution on its solve worker. Options that
// depend on the scene (--camera, --edit) fail before the view factors.
#include <cstdio>

#include "app/commands.h"
#include "app/session_options.h"
#include "core/atomic_file.h"
#include "core/interrupt.h"
#include "core/log.h"
#include "core/strings.h"
#include "core/timer.h"
#include "image/camera.h"
#include "image/exposure.h"
#include "pipeline/backend_registry.h"

#if DAISY_HAVE_VIEWER
#include "viewer/display_values.h"
#include "viewer/material_edit.h"
#include "viewer/viewer.h"
#endif

namespace daisy::app {
namespace {

int runView(const CommonOptions& options, const ViewOptions& view) {
#if DAISY_HAVE_VIEWER
    const Clock::time_point started = Clock::now();
    auto exposure = parseExposure(view.exposure);
    if (!exposure) {
        logError(concat("--exposure: ", exposure.error().message));
        return 2;
    }
    if (!view.display.empty()) {
        if (auto display = viewer::parseDisplay(view.display); !display) {
            logError(display.error().message);
            return 2;
        }
    }
    std::vector<viewer::MaterialEdit> edits;
    for (const std::string& text : view.edits) {
        auto edit = viewer::parseMaterialEdit(text);
        if (!edit) {
            logError(edit.error().message);
            return 2;
        }
        edits.push_back(std::move(*edit));
    }
    const auto checkScene = [&](const Scene& scene) -> Expected<void> {
        auto camera = chooseCamera(scene, view.camera, double(view.width) / double(view.height));
        if (!camera) return camera.error();
        for (const viewer::MaterialEdit& edit : edits) {
            auto targets = viewer::editTargets(scene, edit);
            if (!targets) return targets.error();
        }
        return {};
    };
    if (const auto unavailable = viewer::viewerUnavailable(options.device);
        !unavailable.why.empty()) {
        logError(unavailable.why);
        return unavailable.status;
    }
    logVerbose(concat("view: display and Vulkan device checked ",
                      formatNumber(secondsSince(started) * 1e3, 3), " ms after the start"));
    // An unwritable --screenshot fails now, not after the frames (core/atomic_file.h).
    auto screenshot = reserveOutputs({view.screenshotPath, view.saveMaterialsPath});
    if (!screenshot) {
        logError(screenshot.error().message);
        return 2;
    }
    // An explicit --backend that cannot run here fails now, not in the window.
    if (options.backend != "auto") {
        if (auto runs = checkBackendRunsHere(options.backend); !runs) {
            logError(concat("--backend ", options.backend, ": ", runs.error().message));
            return 2;
        }
    }
    auto session = openSession(options, PatchSizeDefault::Automatic, checkScene);
    if (!session) return 2;
    logVerbose(concat("view: scene, patches, E and M ready ",
                      formatNumber(secondsSince(started) * 1e3, 3), " ms after the start"));
    viewer::ViewerOptions settings;
    settings.startedAt = started;
    settings.device = options.device;
    settings.camera = view.camera;
    settings.width = view.width;
    settings.height = view.height;
    settings.exposure = *exposure;
    settings.frames = view.frames;
    settings.screenshotPath = view.screenshotPath;
    settings.saveMaterialsPath = view.saveMaterialsPath;
    settings.edits = view.edits;
    settings.exerciseWindow = view.exerciseWindow;
    settings.panel = view.panel;
    settings.wavelengthsText = options.wavelengths;
    settings.display = view.display;
    if (!view.pick.empty()) {
        int x = 0, y = 0;
        std::sscanf(view.pick.c_str(), "%d,%d", &x, &y);  // CLI11 checked the form
        settings.pick = std::array<double, 2>{double(x), double(y)};
    }
    return viewer::runViewer(std::move(*session), settings);
#else
    (void)options;
    (void)view;
    return notBuiltYet("view", "the viewer (this build has DAISY_BUILD_VIEWER=OFF)");
#endif
}

}  // namespace

void addViewCommand(CLI::App& app, CommandContext& context) {
    auto view = std::make_shared<ViewOptions>();
    CLI::App* command = context.add(app, "view", "Interactive viewer with a materials editor");
    command->add_option("--screenshot", view->screenshotPath, "Save a PNG of the last frame");
    command->add_option("--save-materials", view->saveMaterialsPath,
                        "Write the edited materials as a --materials JSON file (at the last "
                        "frame; the panel's save button default)");
    command->add_option("--frames", view->frames, "Frames to show, then exit")
        ->check(CLI::Range(1, 1000000));
    command->add_option("--camera", view->camera, "Camera name or index");
    command->add_option("--width", view->width, "Window width")
        ->capture_default_str()
        ->check(CLI::Range(1, 16384));
    command->add_option("--height", view->height, "Window height")
        ->capture_default_str()
        ->check(CLI::Range(1, 16384));
    command->add_option("--exposure", view->exposure, "Exposure in EV, or auto")
        ->capture_default_str();
    command->add_option("--edit", view->edits, "Material edit NAME.FIELD=VALUE (repeatable)");
    command->add_flag("--exercise-window", view->exerciseWindow,
                      "Resize and minimise the window during the frames (tests)");
    command->add_flag("--panel", view->panel, "Show the panel in the --frames mode too");
    command->add_option(
        "--display", view->display,
        "colour | luminance | wavelength:NM, and flat, wireframe (comma-separated)");
    command->add_option("--pick", view->pick, "Pick the patch under pixel X,Y as a click would")
        ->check(CLI::Validator(
            [](std::string& text) {
                int x = 0, y = 0;
                char end = 0;
                return std::sscanf(text.c_str(), "%d,%d%c", &x, &y, &end) == 2 && x >= 0 && y >= 0
                    ? std::string()
                    : "'" + text + "' is not X,Y (pixels)";
            },
            "X,Y"));
    context.onRun(command, [&common = context.common, view] { return runView(common, *view); });
}

}  // namespace daisy::app
