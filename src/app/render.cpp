// `daisy render SCENE -o out.png|.exr|.pfm` (DESIGN.md sections 7 and 9, docs/rendering.md):
// the session (pipeline/session.h, with an automatic patch size unless --subdivide: F from the
// cache or a backend, then the solve), its smooth per-corner radiance in CIE XYZ (and every
// wavelength sample for --spectral-exr) -> a ray-cast image -> exposure -> the file, and a
// closing summary: the time of each stage, the solve, peak memory and what was skipped.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/session_options.h"
#include "core/atomic_file.h"
#include "core/interrupt.h"
#include "core/log.h"
#include "core/memory.h"
#include "core/progress.h"
#include "core/strings.h"
#include "core/timer.h"
#include "hierarchical/hierarchical_transport.h"
#include "image/camera.h"
#include "image/exposure.h"
#include "image/image_io.h"
#include "image/radiosity_image.h"
#include "image/renderer.h"
#include "pathtrace/path_tracer.h"

namespace daisy::app {
namespace {

enum class ImageFormat { Png, Exr, Pfm };

ImageFormat formatOf(const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".exr") return ImageFormat::Exr;
    if (ext == ".pfm") return ImageFormat::Pfm;
    return ImageFormat::Png;  // CLI11 accepted only .png, .exr and .pfm
}

std::string percentOf(uint64_t part, uint64_t whole) {
    return whole ? concat(formatNumber(100.0 * double(part) / double(whole), 3), "%") : "0%";
}

// Copies `count` channels starting at `first` into an image of their own.
Image channelSlice(const Image& image, int first, int count) {
    Image out(image.width, image.height, count);
    for (std::size_t p = 0; p < std::size_t(image.width) * image.height; ++p) {
        for (int c = 0; c < count; ++c)
            out.pixels[p * count + c] = image.pixels[p * image.channels + first + c];
    }
    return out;
}

// Adds (1 - coverage) x background to linear sRGB, so edge pixels blend with the background.
void addBackground(Image& linearSrgb, const Image& rendered, int coverageChannel,
                   const std::array<double, 3>& background) {
    for (std::size_t p = 0; p < std::size_t(linearSrgb.width) * linearSrgb.height; ++p) {
        const double miss = 1.0 - rendered.pixels[p * rendered.channels + coverageChannel];
        for (int c = 0; c < 3; ++c)
            linearSrgb.pixels[p * 3 + c] += static_cast<float>(miss * background[c]);
    }
}

// What the view factors skipped: with the matrix F, the pairs culled without rays; with the
// hierarchical links, the patch pairs they stand for without a factor of their own.
std::string skippedViewFactors(const Session& session, const FormFactorReport& formFactors) {
    if (const auto* links = dynamic_cast<const HierarchicalTransport*>(&session.transport())) {
        const LinkStats& l = links->linkStats();
        const uint64_t n = session.patches().patchCount();
        return concat("skipped: ", percentOf(n * n - l.nearEntries, n * n),
                      " of the patch pairs have no factor of their own (", formatCount(l.farLinks),
                      " far links between nodes stand for them; ", formatCount(l.nearEntries),
                      " near factors); ", formatCount(l.hidden), " node pairs found hidden, ",
                      formatCount(l.rouletteDropped), " left out by roulette and ",
                      formatCount(l.facingAway), " facing away, with ", formatCount(l.raysCast),
                      " far-link rays");
    }
    const FormFactorStats& s = formFactors.stats;
    return concat("skipped: ", percentOf(s.facingAway, s.pairs), " of patch pairs facing away, ",
                  percentOf(s.clearClusterShafts + s.clearPairShafts, s.pairs),
                  " with a clear shaft and ", percentOf(s.coveredPairs, s.pairs),
                  " covered (no rays); ", percentOf(s.tracedPairs, s.pairs), " traced with ",
                  formatCount(s.raysCast), " rays");
}

// One line on what the run did not compute: the view factors' work left out, the
// wavelengths' independence, UV samples left out.
std::string skippedSummary(const Session& session, const FormFactorReport& formFactors) {
    std::string text = concat(formFactors.fromCache ? "(the cached build) " : "",
                              skippedViewFactors(session, formFactors));
    if (session.fluorescentOperatorCount() == 0) {
        text += "; no fluorescence: the wavelengths were solved independently";
    }
    // `auto` adds UV samples only for UV-emitting lights (over 3% of their power below 400 nm,
    // spectral/spectrum.h) together with fluorescent materials.
    if (!session.facts().hasFluorescence) {
        text += "; no UV samples (no fluorescent material)";
    } else if (!session.facts().hasUvLights) {
        text += "; no UV samples (no UV-emitting light)";
    }
    return text;
}

// Exposure, the background and the file (PNG: exposed sRGB; EXR/PFM: linear radiance, plus
// the wavelength channels for --spectral-exr). `rendered` has Session::patchChannels' layout.
// Returns the exposure scale used.
Expected<double> writeRendered(const RenderOptions& render, const Exposure& exposure,
                               const std::array<double, 3>& background, const Image& rendered,
                               const WavelengthSet& set, bool spectral) {
    const ImageFormat format = formatOf(render.outputPath);
    const int m = static_cast<int>(set.size());
    const int xyzChannel = spectral ? m : 0;
    const Image xyz = channelSlice(rendered, xyzChannel, 3);
    const double scale = exposureScale(exposure, xyz);
    Expected<void> written;
    if (format == ImageFormat::Png) {
        Image srgb = xyzToLinearSrgb(xyz, scale);
        addBackground(srgb, rendered, xyzChannel + 3, background);
        written =
            writePng(render.outputPath, srgb.width, srgb.height, toSrgb8(srgb, Rounding::Dithered));
    } else {
        // Float files are scene-referred: linear sRGB radiance, no exposure.
        Image linear = xyzToLinearSrgb(xyz, 1.0);
        addBackground(linear, rendered, xyzChannel + 3, background);
        if (format == ImageFormat::Pfm) {
            written = writePfm(render.outputPath, linear);
        } else if (!spectral) {
            linear.channelNames = {"R", "G", "B"};
            written = writeExr(render.outputPath, linear);
        } else {
            Image all(linear.width, linear.height, 3 + m);
            all.channelNames = {"R", "G", "B"};
            for (int k = 0; k < m; ++k)
                all.channelNames.push_back(spectralChannelName(set.wavelengthNm(k)));
            for (std::size_t p = 0; p < std::size_t(all.width) * all.height; ++p) {
                for (int c = 0; c < 3; ++c)
                    all.pixels[p * all.channels + c] = linear.pixels[p * 3 + c];
                for (int k = 0; k < m; ++k)
                    all.pixels[p * all.channels + 3 + k] =
                        rendered.pixels[p * rendered.channels + k];
            }
            written = writeExr(render.outputPath, all);
        }
    }
    if (!written) return written.error();
    return scale;
}

std::string exposureSummary(ImageFormat format, const Exposure& exposure, double scale) {
    return format != ImageFormat::Png ? "linear, no exposure"
                                      : concat(exposure.automatic ? "auto " : "", "exposure ",
                                               formatNumber(std::log2(scale), 3), " EV");
}

// `--integrator path`: the path tracer (pathtrace/path_tracer.h) on the session's scene and
// wavelength set, no view factors and no solve; then the same exposure and file as radiosity.
int pathTracedRender(const CommonOptions& options, const RenderOptions& render,
                     const Session& session, const Camera& camera, const RenderSettings& image,
                     const std::string& cameraName, const Timer& total) {
    auto exposure = parseExposure(render.exposure);  // checked by runRender
    const auto background = parseBackground(render.background);
    PathTraceSettings settings;
    settings.width = image.width;
    settings.height = image.height;
    settings.samplesPerPixel = render.samplesPerPixel;
    settings.seed = static_cast<uint32_t>(options.seed);
    settings.threads = options.threads;
    settings.spectral = render.spectralExr;
    auto traced =
        pathTrace(session.scene(), session.wavelengths(), camera, settings, &interruptToken());
    if (!traced) {
        logStageError(Error{concat(options.scenePath, ": ", traced.error().message)});
        return 2;
    }
    // Only SIGINT / SIGTERM cancel the interrupt token: the watchdog's line and 130.
    if (traced->cancelled) exitInterrupted();
    Timer stage;
    auto scale = writeRendered(render, *exposure, *background, traced->image, session.wavelengths(),
                               render.spectralExr);
    if (!scale) {
        logError(scale.error().message);
        return 1;
    }
    const double writeSeconds = stage.seconds();
    logInfo(concat("render: wrote ", render.outputPath, " (", image.width, " x ", image.height,
                   ", path traced, ", render.samplesPerPixel, " spp, ", cameraName, ", ",
                   exposureSummary(formatOf(render.outputPath), *exposure, *scale), ")"));
    logInfo(concat("  noise: relative RMS standard error of luminance ",
                   formatNumber(100 * traced->relativeNoise, 3), "% (per-pixel variance of the ",
                   "mean; a quarter of it needs 16x the samples)"));
    logInfo(concat("  time: load ", formatDuration(session.timings().loadSeconds), ", path trace ",
                   formatDuration(traced->seconds), " (", formatSi(double(traced->rays)), " rays, ",
                   formatSi(double(traced->rays) / std::max(traced->seconds, 1e-9)),
                   " rays/s), write ", formatDuration(writeSeconds), "; total ",
                   formatDuration(total.seconds())));
    logInfo(concat("  ", session.wavelengths().size(), " wavelengths (",
                   session.wavelengths().name(),
                   "); peak memory: ", formatBytes(double(peakResidentBytes()))));
    return 0;
}

int runRender(const CommonOptions& options, const RenderOptions& render) {
    const Timer total;
    const ImageFormat format = formatOf(render.outputPath);
    if (render.spectralExr && format != ImageFormat::Exr) {
        logError(concat("--spectral-exr: the output ", render.outputPath, " is not an .exr"));
        return 2;
    }
    auto exposure = parseExposure(render.exposure);
    if (!exposure) {
        logError(concat("--exposure: ", exposure.error().message));
        return 2;
    }
    const auto background = parseBackground(render.background);  // CLI11 checked it
    // An unwritable output fails now, not after the solve (core/atomic_file.h).
    auto reserved = AtomicOutput::open(render.outputPath);
    if (!reserved) {
        logError(reserved.error().message);
        return 2;
    }

    // The camera is chosen as soon as the scene is loaded, so a bad --camera fails fast. The
    // image height defaults to the width over the camera's aspect ratio (4:3 without one); the
    // rays then follow the image's aspect with the camera's vertical field of view.
    Camera camera;
    bool framed = false;
    int width = render.width, height = render.height;
    const auto chooseCameraFor = [&](const Scene& scene) -> Expected<void> {
        framed = render.camera.empty() && scene.cameras.empty();
        const int fallbackHeight = std::max(1, int(std::lround(width * 0.75)));
        auto chosen = chooseCamera(scene, render.camera,
                                   double(width) / double(height > 0 ? height : fallbackHeight));
        if (!chosen) return chosen.error();
        camera = *chosen;
        if (height == 0) {
            height = camera.aspectRatio > 0
                ? std::max(1, int(std::lround(width / camera.aspectRatio)))
                : fallbackHeight;
        }
        camera.aspectRatio = 0;
        return {};
    };
    auto session = openSession(options, PatchSizeDefault::Automatic, chooseCameraFor);
    if (!session) return 2;
    const bool spectral = render.spectralExr;
    const int m = static_cast<int>(session->system().wavelengthCount);
    const int channels = ChannelLayout{std::size_t(m), spectral}.count();
    RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.samplesPerPixel = render.samplesPerPixel;
    settings.edgeSamplesPerPixel = render.edgeSamplesPerPixel;
    settings.threads = options.threads;
    settings.maxMemoryBytes = options.maxMemoryBytes;
    // The image's memory is known now: refuse it before the view factors, not after.
    if (const uint64_t bytes = renderImageBytes(settings, channels);
        bytes > options.maxMemoryBytes) {
        logError(concat(options.scenePath, ": a ", width, " x ", height, " image of ", channels,
                        " channels needs about ", formatBytes(double(bytes)),
                        ", over --max-memory ", formatBytes(double(options.maxMemoryBytes))));
        return 2;
    }
    const std::string cameraName =
        framed ? "automatic framing" : concat("camera '", camera.name, "'");
    if (render.integrator == "path") {
        return pathTracedRender(options, render, *session, camera, settings, cameraName, total);
    }
    FormFactorReport formFactors;
    if (!buildAndSolve(*session, &formFactors)) return 2;
    const SolverResult& solved = session->solution();

    // Shade and ray cast (image/radiosity_image.h): the smooth per-corner radiance, or with
    // --gather direct that without the emitters' direct light plus the light per sample.
    const GatherMode gather = *parseGatherMode(render.gather);  // CLI11 checked it
    DirectLightSettings direct;
    direct.shadowRays = render.gatherRays;
    direct.seed = static_cast<uint32_t>(options.seed);
    NearFieldSettings nearField;
    nearField.radius = render.nearRadius;
    RadiosityImageTimes imageTimes;
    auto rendered = renderRadiosityImage(*session, camera, settings, gather, direct, spectral,
                                         &imageTimes, nearField);
    if (!rendered) {
        logError(concat(options.scenePath, ": ", rendered.error().message));
        return 1;
    }
    const bool gatherDirect = gather != GatherMode::None;
    const double shadeSeconds = imageTimes.shadeSeconds;
    const double renderSeconds = imageTimes.renderSeconds;
    const double gatherSeconds = imageTimes.gatherSeconds;

    // Exposure and the file.
    const Timer stage;
    auto scale =
        writeRendered(render, *exposure, *background, *rendered, session->wavelengths(), spectral);
    if (!scale) {
        logError(scale.error().message);
        return 1;
    }
    const double writeSeconds = stage.seconds();

    const Session& s = *session;
    const SessionTimings& t = s.timings();
    const std::string exposureText = exposureSummary(format, *exposure, *scale);
    logInfo(concat("render: wrote ", render.outputPath, " (", width, " x ", height, ", ",
                   render.samplesPerPixel, " spp",
                   render.edgeSamplesPerPixel > render.samplesPerPixel
                       ? concat(" (", render.edgeSamplesPerPixel, " at ",
                                formatCount(imageTimes.edgePixels), " edge pixels)")
                       : std::string(),
                   ", ", cameraName, ", gather ", render.gather, ", ", exposureText,
                   spectral ? concat(", ", m, " spectral channels") : "", ")"));
    logInfo(concat(
        "  time: load ", formatDuration(t.loadSeconds), ", mesh ", formatDuration(t.meshSeconds),
        ", view factors ", formatDuration(t.viewFactorSeconds),
        formFactors.fromCache ? " (from the cache)" : "", ", solve ",
        formatDuration(t.solveSeconds), ", shade ", formatDuration(shadeSeconds), ", render ",
        formatDuration(renderSeconds),
        gather == GatherMode::Near ? concat(", near field ", formatDuration(imageTimes.nearSeconds))
                                   : "",
        gatherDirect ? concat(", final gather ", formatDuration(gatherSeconds)) : "", ", write ",
        formatDuration(writeSeconds), "; total ", formatDuration(total.seconds())));
    logInfo(concat("  patches: ", formatCount(s.patches().patchCount()), " from ",
                   formatCount(s.scene().mesh.triangleCount()), " triangles (",
                   s.patchMaxEdge() == 0 ? std::string("input triangles")
                                         : concat(s.automaticPatchSize() ? "automatic " : "",
                                                  "--subdivide ", s.patchMaxEdge()),
                   "); ", s.system().wavelengthCount, " wavelengths (", s.wavelengths().name(),
                   "); solve ", solved.iterations, " iterations, residual ",
                   formatNumber(solved.residual, 3), solved.converged ? "" : " (not converged)"));
    logInfo(concat("  ", skippedSummary(s, formFactors)));
    if (gather == GatherMode::Near) {
        logInfo(concat("  near field: ", formatCount(imageTimes.nearPairs), " neighbour pairs, ",
                       formatCount(imageTimes.exactNearPairs),
                       " of them gathered exactly at every sample"));
    }
    logInfo(concat("  peak memory: ", formatBytes(double(peakResidentBytes()))));
    return 0;
}

}  // namespace

void addRenderCommand(CLI::App& app, CommandContext& context) {
    auto render = std::make_shared<RenderOptions>();
    CLI::App* command = context.add(app, "render", "Solve a scene and render it to an image");
    command->add_option("-o,--output", render->outputPath, "Image file (.png, .exr, .pfm)")
        ->check([](const std::string& path) {
            for (const char* ext : {".png", ".exr", ".pfm"}) {
                if (path.size() > 4 && path.compare(path.size() - 4, 4, ext) == 0) return "";
            }
            return "the image must end in .png, .exr or .pfm";
        })
        ->capture_default_str();
    command->add_option("--width", render->width, "Image width")
        ->capture_default_str()
        ->check(CLI::Range(1, 16384));
    command
        ->add_option("--height", render->height,
                     "Image height (default: width / the camera's aspect ratio, else 3/4)")
        ->check(CLI::Range(1, 16384));
    command->add_option("--camera", render->camera, "Camera name or index");
    command->add_option("--spp", render->samplesPerPixel, "Samples per pixel")
        ->check(CLI::Range(1, 4096));
    command
        ->add_option("--edge-spp", render->edgeSamplesPerPixel,
                     "Samples per pixel on silhouettes, creases and material boundaries "
                     "(radiosity; 0 = --spp everywhere)")
        ->check(CLI::Range(0, 4096))
        ->capture_default_str();
    command->add_option("--exposure", render->exposure, "Exposure in EV, or auto")
        ->check(CLI::Validator(
            [](std::string& text) {
                return text == "auto" || CLI::Number(text).empty()
                    ? std::string()
                    : "'" + text + "' is not an exposure: use a number of EV or auto";
            },
            "EV|auto"));
    command->add_flag("--spectral-exr", render->spectralExr,
                      "EXR with one channel per wavelength sample (Fichet et al. 2021)");
    command->add_option("--background", render->background, "R,G,B of rays that miss, 0..1")
        ->check(CLI::Validator(
            [](std::string& text) {
                return parseBackground(text) ? std::string()
                                             : "'" + text + "' is not R,G,B with values in [0, 1]";
            },
            "R,G,B"))
        ->capture_default_str();
    command
        ->add_option("--integrator", render->integrator,
                     "radiosity, or path: the path-traced reference (no view factors)")
        ->check(CLI::IsMember({"radiosity", "path"}))
        ->capture_default_str();
    command
        ->add_option("--gather", render->gather,
                     "Final gather: none (smooth vertex radiance), direct (exact direct light "
                     "per sample) or near (direct, plus the indirect light from patches within "
                     "--near-radius per sample)")
        ->check(CLI::IsMember({"none", "direct", "near"}))
        ->capture_default_str();
    command
        ->add_option("--near-radius", render->nearRadius,
                     "Radius of --gather near's per-sample indirect light, in patch sizes")
        ->check(finiteNumber(0, 16))
        ->capture_default_str();
    command
        ->add_option(
            "--gather-rays", render->gatherRays,
            "Shadow segments per penumbra pixel of the direct gather (1/16 of it elsewhere)")
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    context.onRun(command,
                  [&common = context.common, render] { return runRender(common, *render); });
}

}  // namespace daisy::app
