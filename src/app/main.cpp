// `daisy`: parse the command line, call the library, print. DESIGN.md section 9.
#include <cstdio>

#include "app/commands.h"
#include "core/interrupt.h"
#include "core/log.h"
#include "pipeline/backend_registry.h"

using namespace daisy::app;

int main(int argc, char** argv) {
    CLI::App app{"DaisyRiot: spectral radiosity with fluorescent materials", "daisy"};
    app.require_subcommand(1);
    std::string version = "daisy 0.1.0 (backends:";
    for (const std::string& name : daisy::builtInBackendNames())
        version += " " + name;
    version += ")";
    app.set_version_flag("--version", version);

    CommonOptions common;
    RenderOptions render;
    ViewOptions view;
    ExportOptions exports;
    ValidateOptions validate;
    BenchOptions bench;

    auto* renderCmd = app.add_subcommand("render", "Solve a scene and render it to an image");
    addCommonOptions(*renderCmd, common);
    renderCmd->add_option("-o,--output", render.outputPath, "Image file (.png, .exr, .pfm)")
        ->check([](const std::string& path) {
            for (const char* ext : {".png", ".exr", ".pfm"}) {
                if (path.size() > 4 && path.compare(path.size() - 4, 4, ext) == 0) return "";
            }
            return "the image must end in .png, .exr or .pfm";
        })
        ->capture_default_str();
    renderCmd->add_option("--width", render.width, "Image width")
        ->capture_default_str()
        ->check(CLI::Range(1, 16384));
    renderCmd
        ->add_option("--height", render.height,
                     "Image height (default: width / the camera's aspect ratio, else 3/4)")
        ->check(CLI::Range(1, 16384));
    renderCmd->add_option("--camera", render.camera, "Camera name or index");
    renderCmd->add_option("--spp", render.samplesPerPixel, "Samples per pixel")
        ->check(CLI::Range(1, 4096));
    renderCmd
        ->add_option("--edge-spp", render.edgeSamplesPerPixel,
                     "Samples per pixel on silhouettes, creases and material boundaries "
                     "(radiosity; 0 = --spp everywhere)")
        ->check(CLI::Range(0, 4096))
        ->capture_default_str();
    renderCmd->add_option("--exposure", render.exposure, "Exposure in EV, or auto")
        ->check(CLI::Validator(
            [](std::string& text) {
                return text == "auto" || CLI::Number(text).empty()
                    ? std::string()
                    : "'" + text + "' is not an exposure: use a number of EV or auto";
            },
            "EV|auto"));
    renderCmd->add_flag("--spectral-exr", render.spectralExr,
                        "EXR with one channel per wavelength sample (Fichet et al. 2021)");
    renderCmd->add_option("--background", render.background, "R,G,B of rays that miss, 0..1")
        ->check(CLI::Validator(
            [](std::string& text) {
                return parseBackground(text) ? std::string()
                                             : "'" + text + "' is not R,G,B with values in [0, 1]";
            },
            "R,G,B"))
        ->capture_default_str();
    renderCmd
        ->add_option("--integrator", render.integrator,
                     "radiosity, or path: the path-traced reference (no view factors)")
        ->check(CLI::IsMember({"radiosity", "path"}))
        ->capture_default_str();
    renderCmd
        ->add_option("--gather", render.gather,
                     "Final gather: none (smooth vertex radiance), direct (exact direct light "
                     "per sample) or near (direct, plus the indirect light from patches within "
                     "--near-radius per sample)")
        ->check(CLI::IsMember({"none", "direct", "near"}))
        ->capture_default_str();
    renderCmd
        ->add_option("--near-radius", render.nearRadius,
                     "Radius of --gather near's per-sample indirect light, in patch sizes")
        ->check(CLI::Range(0.0, 16.0))
        ->capture_default_str();
    renderCmd
        ->add_option(
            "--gather-rays", render.gatherRays,
            "Shadow segments per penumbra pixel of the direct gather (1/16 of it elsewhere)")
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();

    auto* solveCmd = app.add_subcommand("solve", "Solve spectral radiosity");
    addCommonOptions(*solveCmd, common);
    solveCmd->add_option("--patches-out", exports.patchesPath, "Write patches as CSV");

    auto* formFactorsCmd = app.add_subcommand("formfactors", "Compute the view-factor matrix");
    addCommonOptions(*formFactorsCmd, common);
    formFactorsCmd->add_option("-o,--output", exports.matrixPath, "Matrix Market file")->required();
    formFactorsCmd->add_option("--patches-out", exports.patchesPath, "Write patches as CSV");

    auto* infoCmd = app.add_subcommand("info", "Describe a scene and the cost of solving it");
    addCommonOptions(*infoCmd, common);

    auto* viewCmd = app.add_subcommand("view", "Interactive viewer with a materials editor");
    addCommonOptions(*viewCmd, common);
    viewCmd->add_option("--screenshot", view.screenshotPath, "Save a PNG of the last frame");
    viewCmd->add_option("--frames", view.frames, "Frames to show, then exit")
        ->check(CLI::Range(1, 1000000));
    viewCmd->add_option("--camera", view.camera, "Camera name or index");
    viewCmd->add_option("--width", view.width, "Window width")
        ->capture_default_str()
        ->check(CLI::Range(1, 16384));
    viewCmd->add_option("--height", view.height, "Window height")
        ->capture_default_str()
        ->check(CLI::Range(1, 16384));
    viewCmd->add_option("--exposure", view.exposure, "Exposure in EV, or auto")
        ->capture_default_str();
    viewCmd->add_option("--edit", view.edits, "Material edit NAME.FIELD=VALUE (repeatable)");
    viewCmd->add_flag("--exercise-window", view.exerciseWindow,
                      "Resize and minimise the window during the frames (tests)");
    viewCmd->add_flag("--panel", view.panel, "Show the panel in the --frames mode too");
    viewCmd->add_option(
        "--display", view.display,
        "colour | luminance | wavelength:NM, and flat, wireframe (comma-separated)");
    viewCmd->add_option("--pick", view.pick, "Pick the patch under pixel X,Y as a click would")
        ->check(CLI::Validator(
            [](std::string& text) {
                int x = 0, y = 0;
                char end = 0;
                return std::sscanf(text.c_str(), "%d,%d%c", &x, &y, &end) == 2 && x >= 0 && y >= 0
                    ? std::string()
                    : "'" + text + "' is not X,Y (pixels)";
            },
            "X,Y"));

    auto* validateCmd = app.add_subcommand("validate", "Compare a backend's matrix to another's");
    addCommonOptions(*validateCmd, common);
    validateCmd->add_option("--against", validate.against, "Backend to compare with")
        ->check(CLI::IsMember({"reference", "cpu"}))
        ->capture_default_str();
    validateCmd->add_option("--rtol", validate.relativeTolerance, "Relative tolerance per entry")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    validateCmd->add_option("--atol", validate.absoluteTolerance, "Absolute tolerance per entry")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    validateCmd->add_option("--worst", validate.worstShown, "Worst entries to list")
        ->check(CLI::Range(0, 1000000))
        ->capture_default_str();

    auto* benchCmd = app.add_subcommand("bench", "Benchmark run time against error");
    addCommonOptions(*benchCmd, common, /*sceneRequired=*/false);
    benchCmd->add_flag("--stress", bench.stress, "Run the numerical stress suite");
    benchCmd->add_flag("--quick", bench.quick, "Reduced sizes (what ctest runs)");
    benchCmd->add_option("-o,--output", bench.outputPath, "CSV of the results");
    benchCmd
        ->add_option("--reference", bench.reference,
                     "What error is measured against: path (the path-traced reference) or daisy "
                     "(the settings sweep against a converged fine solution)")
        ->check(CLI::IsMember({"daisy", "path"}))
        ->capture_default_str();
    benchCmd
        ->add_option("--reference-spp", bench.referenceSpp,
                     "Samples per pixel of the path-traced reference (at most; traced in chunks "
                     "of 1,024, cached and resumed)")
        ->check(CLI::Range(1, 1 << 20))
        ->capture_default_str();
    benchCmd
        ->add_option("--reference-noise", bench.referenceNoise,
                     "Percent: stop the path-traced reference once its relative RMS noise is "
                     "under this (0: run to --reference-spp)")
        ->check(CLI::Range(0.0, 100.0))
        ->capture_default_str();

    CacheOptions cacheOptions;
    auto* cacheCmd = addCacheCommand(app, cacheOptions);

    const std::string first = argc > 1 ? argv[1] : "";
    if (!first.empty() && first[0] != '-' &&
        app.get_subcommands([&](CLI::App* sub) { return sub->check_name(first); }).empty()) {
        std::fprintf(stderr,
                     "error: unknown command '%s' (expected render, solve, formfactors, info, "
                     "view, validate, bench or cache; see daisy --help)\n",
                     first.c_str());
        return 2;
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "error: %s (see daisy --help)\n", e.what());
        return 2;
    }

    // SIGINT / SIGTERM: temporaries removed, one line, exit 130 (core/interrupt.h).
    daisy::installInterruptHandlers();
    finishCommonOptions(common);
    daisy::setVerbosity(common.quiet         ? daisy::Verbosity::Quiet
                            : common.verbose ? daisy::Verbosity::Verbose
                                             : daisy::Verbosity::Normal);

    if (*cacheCmd) return runCache(cacheOptions);
    if (*infoCmd) return runInfo(common);
    if (*formFactorsCmd) return runFormFactors(common, exports);
    if (*validateCmd && common.backend != "vulkan" && common.backend != "cuda") {
        daisy::logError("daisy validate: --backend must be vulkan or cuda");
        return 2;
    }
    if (*renderCmd) return runRender(common, render);
    if (*solveCmd) return runSolve(common, exports);
    if (*viewCmd) return runView(common, view);
    if (*validateCmd) return runValidate(common, validate);
    if (*benchCmd) return runBench(common, bench);
    return 1;
}
