// `daisy render SCENE -o out.png|.exr|.pfm` (DESIGN.md sections 7 and 9, docs/rendering.md):
// the whole pipeline (app/pipeline.h, with an automatic patch size unless --subdivide), then
// per-patch radiance L = B / pi -> CIE XYZ (and every wavelength sample for --spectral-exr) ->
// smooth per-corner values -> a ray-cast image -> exposure -> the file, and a closing summary:
// the time of each stage, the solve, peak memory and what was skipped.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/pipeline.h"
#include "core/log.h"
#include "core/memory.h"
#include "core/progress.h"
#include "core/strings.h"
#include "core/timer.h"
#include "image/camera.h"
#include "image/exposure.h"
#include "image/image_io.h"
#include "image/renderer.h"
#include "image/vertex_radiance.h"

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

// Per-patch values for the renderer: [L_0 .. L_{m-1} when spectral] X Y Z coverage, where
// L = B / pi is the radiance of a Lambertian emitter of exitance B and coverage is 1 (so the
// rendered coverage channel is the fraction of a pixel's samples that hit the scene).
std::vector<float> patchChannels(const SolvedScene& solved, bool spectral, int channels) {
    const std::size_t n = solved.system.patchCount, m = solved.system.wavelengthCount;
    const std::vector<double>& b = solved.solution.radiosity;
    std::vector<float> values(n * std::size_t(channels));
    std::vector<double> radiance(m);
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t k = 0; k < m; ++k)
            radiance[k] = b[i * m + k] / std::numbers::pi;
        float* out = values.data() + i * std::size_t(channels);
        if (spectral) {
            for (std::size_t k = 0; k < m; ++k)
                *out++ = static_cast<float>(radiance[k]);
        }
        const Xyz xyz = solved.wavelengths.toXyz(radiance);
        *out++ = static_cast<float>(xyz[0]);
        *out++ = static_cast<float>(xyz[1]);
        *out++ = static_cast<float>(xyz[2]);
        *out = 1.0f;
    }
    return values;
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

// One line on what the run did not compute: pairs culled without rays, the wavelengths'
// independence, UV samples left out.
std::string skippedSummary(const SolvedScene& solved) {
    const FormFactorStats& s = solved.formFactors.result.stats;
    std::string text = concat(
        "skipped: ", percentOf(s.facingAway, s.pairs), " of patch pairs facing away, ",
        percentOf(s.clearClusterShafts + s.clearPairShafts, s.pairs), " with a clear shaft and ",
        percentOf(s.coveredPairs, s.pairs), " covered (no rays); ",
        percentOf(s.tracedPairs, s.pairs), " traced with ", formatCount(s.raysCast), " rays");
    if (solved.fluorescentOperators == 0) {
        text += "; no fluorescence: the wavelengths were solved independently";
    }
    // `auto` adds UV samples only for UV-emitting lights (over 3% of their power below 400 nm,
    // spectral/spectrum.h) together with fluorescent materials.
    if (!solved.facts.hasFluorescence) {
        text += "; no UV samples (no fluorescent material)";
    } else if (!solved.facts.hasUvLights) {
        text += "; no UV samples (no UV-emitting light)";
    }
    return text;
}

}  // namespace

int runRender(const CommonOptions& options, const RenderOptions& render) {
    const auto started = Clock::now();
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
    // An output directory that does not exist fails now, not after the solve.
    const std::filesystem::path directory =
        std::filesystem::absolute(render.outputPath).parent_path();
    if (!std::filesystem::is_directory(directory)) {
        logError(
            concat(render.outputPath, ": the directory ", directory.string(), " does not exist"));
        return 1;
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
    auto solved = solveScene(options, DefaultPatchSize::Automatic, chooseCameraFor);
    if (!solved) {
        logError(solved.error().message);
        return 2;
    }

    // Shade: per-patch radiance -> per-corner values.
    auto start = Clock::now();
    const bool spectral = render.spectralExr;
    const int m = static_cast<int>(solved->system.wavelengthCount);
    const int xyzChannel = spectral ? m : 0;
    const int channels = xyzChannel + 4;  // [spectral], X, Y, Z, coverage
    const std::vector<float> corners =
        cornerValues(solved->patches, patchChannels(*solved, spectral, channels), channels);
    const double shadeSeconds = secondsSince(start);

    start = Clock::now();
    RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.samplesPerPixel = render.samplesPerPixel;
    settings.threads = options.threads;
    const std::vector<float> missValue(std::size_t(channels), 0.0f);
    auto rendered =
        renderCornerValues(solved->patches, camera, settings, corners, channels, missValue);
    if (!rendered) {
        logError(concat(options.scenePath, ": ", rendered.error().message));
        return 1;
    }
    const double renderSeconds = secondsSince(start);

    // Exposure and the file.
    start = Clock::now();
    const Image xyz = channelSlice(*rendered, xyzChannel, 3);
    const double scale = exposureScale(*exposure, xyz);
    Expected<void> written;
    if (format == ImageFormat::Png) {
        Image srgb = xyzToLinearSrgb(xyz, scale);
        addBackground(srgb, *rendered, xyzChannel + 3, *background);
        written = writePng(render.outputPath, srgb.width, srgb.height, toSrgb8(srgb));
    } else {
        // Float files are scene-referred: linear sRGB radiance, no exposure.
        Image linear = xyzToLinearSrgb(xyz, 1.0);
        addBackground(linear, *rendered, xyzChannel + 3, *background);
        if (format == ImageFormat::Pfm) {
            written = writePfm(render.outputPath, linear);
        } else if (!spectral) {
            linear.channelNames = {"R", "G", "B"};
            written = writeExr(render.outputPath, linear);
        } else {
            Image all(linear.width, linear.height, 3 + m);
            all.channelNames = {"R", "G", "B"};
            for (int k = 0; k < m; ++k)
                all.channelNames.push_back(
                    spectralChannelName(solved->wavelengths.wavelengthNm(k)));
            for (std::size_t p = 0; p < std::size_t(all.width) * all.height; ++p) {
                for (int c = 0; c < 3; ++c)
                    all.pixels[p * all.channels + c] = linear.pixels[p * 3 + c];
                for (int k = 0; k < m; ++k)
                    all.pixels[p * all.channels + 3 + k] =
                        rendered->pixels[p * rendered->channels + k];
            }
            written = writeExr(render.outputPath, all);
        }
    }
    if (!written) {
        logError(written.error().message);
        return 1;
    }
    const double writeSeconds = secondsSince(start);

    const SolvedScene& s = *solved;
    const std::string cameraName =
        framed ? "automatic framing" : concat("camera '", camera.name, "'");
    const std::string exposureText = format != ImageFormat::Png
        ? "linear, no exposure"
        : concat(exposure->automatic ? "auto " : "", "exposure ", formatNumber(std::log2(scale), 3),
                 " EV");
    logInfo(concat("render: wrote ", render.outputPath, " (", width, " x ", height, ", ",
                   render.samplesPerPixel, " spp, ", cameraName, ", ", exposureText,
                   spectral ? concat(", ", m, " spectral channels") : "", ")"));
    logInfo(concat("  time: load ", formatDuration(s.loadSeconds), ", mesh ",
                   formatDuration(s.meshSeconds), ", view factors ",
                   formatDuration(s.viewFactorSeconds), ", solve ", formatDuration(s.solveSeconds),
                   ", shade ", formatDuration(shadeSeconds), ", render ",
                   formatDuration(renderSeconds), ", write ", formatDuration(writeSeconds),
                   "; total ", formatDuration(secondsSince(started))));
    logInfo(concat(
        "  patches: ", formatCount(s.patches.patchCount()), " from ",
        formatCount(s.scene.mesh.triangleCount()), " triangles (",
        s.maxEdge == 0
            ? std::string("input triangles")
            : concat(s.automaticPatchSize ? "automatic " : "", "--subdivide ", s.maxEdge),
        "); ", s.system.wavelengthCount, " wavelengths (", s.wavelengths.name(), "); solve ",
        s.solution.iterations, " iterations, residual ", formatNumber(s.solution.residual, 3),
        s.solution.converged ? "" : " (not converged)"));
    logInfo(concat("  ", skippedSummary(s)));
    logInfo(concat("  peak memory: ", formatBytes(double(peakResidentBytes()))));
    return 0;
}

}  // namespace daisy::app
