// `daisy bench SCENE --reference path` (issue 16): run time against image error, measured
// against the independent path tracer (pathtrace/path_tracer.h) instead of a finer daisy.
//
// - The reference: the path tracer at --reference-spp samples per pixel on the session's
//   wavelength set, in chunks of up to 1,024 spp with their own seeds (1000, 1001, ...), summed;
//   the sums, the per-pixel variance and the time are cached on disk after every chunk (keyed
//   by the scene file's bytes and the settings), so an interrupted reference resumes and a
//   larger --reference-spp extends the cached one. --reference-noise stops it early once its
//   relative RMS noise is under that level.
// - The path tracer's error-time curve: fresh runs (seed 7, independent of the reference) at
//   1, 4, 16, 64 and 256 spp.
// - The radiosity rows: the automatic patch size (or --subdivide; labelled "auto") and two finer
//   ones (edge / 1.5, / 2), each with --gather none at 1 spp, --gather direct at 1 and 4 spp
//   without edge supersampling, --gather direct at 1 spp with 16 and 64 samples at edges
//   (image/edge_sampling.h), and --gather near at 1 spp with 16 at edges (`daisy render`'s
//   default); a row's time is the whole pipeline (patches, F without the cache, solve, image).
// Error (bench/image_error.h): relative RMS luminance with the reference's own noise taken out,
// and mean CIE76 / CIEDE2000 as displayed at the reference's exposure, emitter pixels and a
// 2-pixel neighbourhood left out. Output: the CSV, a log-log chart of both curves, the reference
// image and the error images of the automatic size's smooth, gathered and default images.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "app/bench_path.h"
#include "app/session_options.h"
#include "bench/chart.h"
#include "bench/image_error.h"
#include "core/atomic_file.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/strings.h"
#include "core/timer.h"
#include "image/camera.h"
#include "image/exposure.h"
#include "image/image_io.h"
#include "image/radiosity_image.h"
#include "pathtrace/path_tracer.h"

namespace daisy::app {
namespace {

constexpr uint32_t kReferenceSeed = 1000;  // chunk c's seed is kReferenceSeed + c
constexpr int kChunkSpp = 1024;
constexpr int kQuickChunkSpp = 32;  // --quick: at most 64 spp, in chunks of 32
constexpr uint32_t kCurveSeed = 7;
constexpr double kTargetError = 0.02;  // the 2% relative RMS luminance
// The radiosity rows' images: final gather, samples per pixel and at edges (0 = uniform).
struct ImageSetting {
    GatherMode gather;
    int samples;
    int edgeSamples;
};
// The first is the smooth image (the viewer's), the last `daisy render`'s default.
constexpr ImageSetting kImageSettings[] = {{GatherMode::None, 1, 0},    {GatherMode::Direct, 1, 0},
                                           {GatherMode::Direct, 4, 0},  {GatherMode::Direct, 1, 16},
                                           {GatherMode::Direct, 1, 64}, {GatherMode::Near, 1, 16}};
constexpr std::size_t kDefaultImage = 5;

// The reference's chunk sums (what the cache holds) and the mean they give.
struct Reference {
    int chunks = 0;
    double seconds = 0;
    std::vector<double> xyzSum;  // per pixel X Y Z, summed over chunks
    std::vector<double> varianceSum;  // per pixel, the chunks' variances of their mean Y, summed
    Image xyz;  // the mean, 3 channels
    Image varianceY;  // of the mean: varianceSum / chunks^2
    double noise = 0;  // relative RMS noise over the kept pixels
};

struct Row {
    std::string kind;  // "path" | "radiosity"
    std::string label;
    double seconds = 0;
    uint64_t patches = 0;
    ImageError error;
};

uint64_t referenceKey(const std::string& scenePath, const std::string& settings) {
    uint64_t hash = 14695981039346656037ull;
    const auto mix = [&](const std::string& bytes) {
        for (unsigned char c : bytes)
            hash = (hash ^ c) * 1099511628211ull;
    };
    std::ifstream file(scenePath, std::ios::binary);
    mix(std::string(std::istreambuf_iterator<char>(file), {}));
    mix(settings);
    return hash;
}

constexpr char kMagic[8] = {'D', 'R', 'P', 'T', 'R', 'E', 'F', '2'};

bool readReference(const std::string& path, uint64_t key, int width, int height, Reference& r) {
    std::ifstream in(path, std::ios::binary);
    char magic[8];
    uint64_t stored = 0;
    int32_t header[3];
    if (!in.read(magic, 8) || !std::equal(magic, magic + 8, kMagic)) return false;
    if (!in.read(reinterpret_cast<char*>(&stored), 8) || stored != key) return false;
    if (!in.read(reinterpret_cast<char*>(header), 12) || header[0] != width ||
        header[1] != height || header[2] < 1)
        return false;
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    Reference read;
    read.chunks = header[2];
    read.xyzSum.resize(pixels * 3);
    read.varianceSum.resize(pixels);
    in.read(reinterpret_cast<char*>(&read.seconds), 8);
    in.read(reinterpret_cast<char*>(read.xyzSum.data()),
            std::streamsize(read.xyzSum.size() * sizeof(double)));
    in.read(reinterpret_cast<char*>(read.varianceSum.data()),
            std::streamsize(read.varianceSum.size() * sizeof(double)));
    if (!in) return false;
    r = std::move(read);
    return true;
}

Expected<void> writeReference(const std::string& path, uint64_t key, int width, int height,
                              const Reference& r) {
    return writeFileAtomically(path, [&](std::FILE* out) {
        const int32_t header[3] = {width, height, r.chunks};
        std::fwrite(kMagic, 1, 8, out);
        std::fwrite(&key, 8, 1, out);
        std::fwrite(header, 4, 3, out);
        std::fwrite(&r.seconds, 8, 1, out);
        std::fwrite(r.xyzSum.data(), sizeof(double), r.xyzSum.size(), out);
        std::fwrite(r.varianceSum.data(), sizeof(double), r.varianceSum.size(), out);
        return std::string();
    });
}

// The mean of the chunks, its variance and its relative RMS noise over `mask`.
void finishReference(Reference& r, int width, int height, const std::vector<uint8_t>& mask) {
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    const double n = r.chunks;
    r.xyz = Image(width, height, 3);
    r.varianceY = Image(width, height, 1);
    Image withCoverage(width, height, 4);
    for (std::size_t p = 0; p < pixels; ++p) {
        for (int c = 0; c < 3; ++c) {
            r.xyz.pixels[p * 3 + c] = float(r.xyzSum[p * 3 + c] / n);
            withCoverage.pixels[p * 4 + c] = r.xyz.pixels[p * 3 + c];
        }
        withCoverage.pixels[p * 4 + 3] = 1;
        r.varianceY.pixels[p] = float(r.varianceSum[p] / (n * n));
    }
    r.noise = relativeRmsNoise(withCoverage, 1, r.varianceY, mask);
}

// Time the path tracer needs for `target`: log-log interpolation between the first row under
// it and the one before; past the curve's end, extrapolated from its last row by the Monte
// Carlo law error ~ 1 / sqrt(time) (`extrapolated` set). NAN without path rows.
double pathTimeTo(const std::vector<Row>& rows, double target, bool& extrapolated) {
    const Row* previous = nullptr;
    extrapolated = false;
    for (const Row& row : rows) {
        if (row.kind != "path") continue;
        const double e = row.error.relativeRmsYDenoised;
        if (e <= target) {
            if (!previous) return row.seconds;
            const double e0 = previous->error.relativeRmsYDenoised;
            const double t = std::log(e0 / target) / std::log(e0 / e);
            return std::exp(std::log(previous->seconds) +
                            t * (std::log(row.seconds) - std::log(previous->seconds)));
        }
        previous = &row;
    }
    if (!previous) return NAN;
    extrapolated = true;
    const double ratio = previous->error.relativeRmsYDenoised / target;
    return previous->seconds * ratio * ratio;
}

std::string stemPath(const std::string& csvPath, const std::string& suffix) {
    std::filesystem::path p(csvPath);
    return (p.parent_path() / (p.stem().string() + suffix)).string();
}

}  // namespace

int runPathBench(const CommonOptions& options, const BenchOptions& bench) {
    if (options.scenePath.empty()) {
        logError("daisy bench --reference path: give a SCENE");
        return 2;
    }
    const int size = bench.quick ? 48 : 256;
    SessionSettings base = sessionSettingsFrom(options, PatchSizeDefault::Automatic);
    base.cacheDirectory.reset();  // every row builds its own F: honest times
    base.logStages = false;
    Camera camera;
    const auto chooseCameraFor = [&](const Scene& scene) -> Expected<void> {
        auto chosen = chooseCamera(scene, "", 1.0);
        if (!chosen) return chosen.error();
        camera = *chosen;
        camera.aspectRatio = 0;
        return {};
    };
    auto first = Session::open(base, chooseCameraFor);
    if (!first) {
        logError(first.error().message);
        return 2;
    }
    // The finer rows' edge: the automatic patch size, or where that keeps the input triangles
    // (0), the median triangle's longest edge.
    double autoEdge = first->patchMaxEdge();
    if (autoEdge == 0) {
        const PatchMesh& patches = first->patches();
        std::vector<double> longest(patches.patchCount());
        for (std::size_t p = 0; p < longest.size(); ++p) {
            const auto& c = patches.patches[p];
            const Vec3d &a = patches.positions[c[0]], &b = patches.positions[c[1]],
                        &d = patches.positions[c[2]];
            longest[p] =
                std::sqrt(std::max({dot(b - a, b - a), dot(d - b, d - b), dot(a - d, a - d)}));
        }
        const auto middle = longest.begin() + std::ptrdiff_t(longest.size() / 2);
        std::nth_element(longest.begin(), middle, longest.end());
        autoEdge = longest.empty() ? 0.0 : *middle;
    }
    auto mask = emitterMask(first->patches(), first->system(), camera, size, size);
    if (!mask) {
        logError(concat(options.scenePath, ": ", mask.error().message));
        return 1;
    }
    const std::string stem = std::filesystem::path(options.scenePath).stem().string();
    const std::string csvPath =
        bench.outputPath.empty() ? concat("bench-path-", stem, ".csv") : bench.outputPath;
    const std::string cachePath = options.cacheDir.empty()
        ? stemPath(csvPath, ".path-reference.bin")
        : (std::filesystem::path(options.cacheDir) / (stem + ".path-reference.bin")).string();

    // The reference: chunks until --reference-spp (rounded up to whole chunks) or, with
    // --reference-noise, until its noise is under that; resumed from and saved to the cache.
    const int total = bench.quick ? std::min(bench.referenceSpp, 64) : bench.referenceSpp;
    const int chunkSpp = std::min(total, bench.quick ? kQuickChunkSpp : kChunkSpp);
    const int chunks = (total + chunkSpp - 1) / chunkSpp;
    const double noiseTarget = bench.referenceNoise / 100;
    const uint64_t key =
        referenceKey(options.scenePath,
                     concat(size, " ", chunkSpp, " ", kReferenceSeed, " ",
                            first->wavelengths().name(), " ", first->wavelengths().size()));
    Reference reference;
    if (readReference(cachePath, key, size, size, reference)) {
        finishReference(reference, size, size, *mask);
        logInfo(concat("bench: path-traced reference read from ", cachePath, " (",
                       formatCount(uint64_t(reference.chunks) * uint64_t(chunkSpp)), " spp)"));
    } else {
        reference.xyzSum.assign(std::size_t(size) * size * 3, 0.0);
        reference.varianceSum.assign(std::size_t(size) * size, 0.0);
    }
    const auto converged = [&] {
        return reference.chunks >= chunks ||
            (noiseTarget > 0 && reference.chunks > 0 && reference.noise <= noiseTarget);
    };
    if (!converged()) {
        logInfo(concat(
            "bench: path tracing the reference (", size, " x ", size, ", up to ",
            formatCount(uint64_t(chunks) * uint64_t(chunkSpp)), " spp in chunks of ", chunkSpp,
            noiseTarget > 0 ? concat(", until its noise is under ", bench.referenceNoise, "%")
                            : std::string(),
            "); saved after each chunk in ", cachePath));
    }
    while (!converged()) {
        PathTraceSettings settings;
        settings.width = settings.height = size;
        settings.samplesPerPixel = chunkSpp;
        settings.seed = kReferenceSeed + uint32_t(reference.chunks);
        settings.threads = options.threads;
        auto traced = pathTrace(first->scene(), first->wavelengths(), camera, settings);
        if (!traced) {
            logError(concat(options.scenePath, ": ", traced.error().message));
            return 2;
        }
        for (std::size_t p = 0; p < std::size_t(size) * size; ++p) {
            for (int c = 0; c < 3; ++c)
                reference.xyzSum[p * 3 + c] += traced->image.pixels[p * traced->image.channels + c];
            reference.varianceSum[p] += traced->varianceY.pixels[p];
        }
        ++reference.chunks;
        reference.seconds += traced->seconds;
        finishReference(reference, size, size, *mask);
        if (auto written = writeReference(cachePath, key, size, size, reference); !written)
            logWarning(concat("bench: ", written.error().message));
        const int left = chunks - reference.chunks;
        logInfo(concat("bench: reference chunk ", reference.chunks, " of ", chunks, " (seed ",
                       settings.seed, "): ", formatNumber(traced->seconds, 3), " s, noise ",
                       formatNumber(100 * reference.noise, 3), "%",
                       left > 0
                           ? concat(", at most ", formatDuration(left * traced->seconds), " to go")
                           : std::string()));
    }
    const int spp = reference.chunks * chunkSpp;
    const double exposure = autoExposureScale(reference.xyz);
    logInfo(concat("bench: reference ", spp, " spp, ", formatNumber(reference.seconds, 3),
                   " s, relative RMS noise ", formatNumber(100 * reference.noise, 3),
                   "% (emitter pixels and 2 around them left out)"));

    std::vector<Row> rows;
    const auto report = [&](const Row& row) {
        char line[256];
        std::snprintf(line, sizeof line, "  %-9s %-26s %9.3f %8llu %9.2f%% %9.2f%% %8.3f %8.3f",
                      row.kind.c_str(), row.label.c_str(), row.seconds,
                      static_cast<unsigned long long>(row.patches),
                      100 * row.error.relativeRmsYDenoised, 100 * row.error.relativeRmsY,
                      row.error.meanDeltaE76, row.error.meanDeltaE2000);
        logInfo(line);
    };
    logInfo(
        "  kind      setting                       time s  patches  rms Y     rms Y raw  dE76     "
        "dE00");

    // The path tracer's own curve.
    std::vector<int> curve =
        bench.quick ? std::vector<int>{1, 4} : std::vector<int>{1, 4, 16, 64, 256};
    for (const int n : curve) {
        PathTraceSettings settings;
        settings.width = settings.height = size;
        settings.samplesPerPixel = n;
        settings.seed = kCurveSeed;
        settings.threads = options.threads;
        settings.showProgress = false;
        auto traced = pathTrace(first->scene(), first->wavelengths(), camera, settings);
        if (!traced) {
            logError(concat(options.scenePath, ": ", traced.error().message));
            return 1;
        }
        Row row{"path", concat(n, " spp"), traced->seconds, 0, {}};
        row.error =
            compareImages(traced->image, reference.xyz, *mask, exposure, &reference.varianceY);
        report(row);
        rows.push_back(row);
    }

    // The radiosity rows.
    RenderSettings image;
    image.width = image.height = size;
    image.threads = options.threads;
    const std::vector<double> divisors =
        bench.quick ? std::vector<double>{1} : std::vector<double>{1, 1.5, 2};
    for (const double divisor : divisors) {
        const Timer timer;
        SessionSettings settings = base;
        settings.subdivideMaxEdge = divisor == 1 ? first->patchMaxEdge() : autoEdge / divisor;
        auto session = Session::open(settings);
        if (!session) {
            logError(session.error().message);
            return 1;
        }
        if (auto f = session->buildFormFactors(); !f) {
            logError(f.error().message);
            return 1;
        }
        if (auto solved = session->solve(); !solved) {
            logError(solved.error().message);
            return 1;
        }
        const double pipelineSeconds = timer.seconds();
        for (const ImageSetting& setting : kImageSettings) {
            const auto [mode, samples, edgeSamples] = setting;
            const Timer imageTimer;
            DirectLightSettings direct;
            direct.seed = static_cast<uint32_t>(options.seed);
            image.samplesPerPixel = samples;
            image.edgeSamplesPerPixel = edgeSamples;
            auto rendered = renderRadiosityImage(*session, camera, image, mode, direct, false);
            if (!rendered) {
                logError(concat(options.scenePath, ": ", rendered.error().message));
                return 1;
            }
            Row row{"radiosity",
                    concat(divisor == 1 ? std::string("auto") : concat("edge/", divisor),
                           ", gather ", gatherModeName(mode), ", ", samples, " spp",
                           edgeSamples > 0 ? concat(" (", edgeSamples, " at edges)") : ""),
                    pipelineSeconds + imageTimer.seconds(),
                    session->patches().patchCount(),
                    {}};
            row.error =
                compareImages(*rendered, reference.xyz, *mask, exposure, &reference.varianceY);
            report(row);
            rows.push_back(row);
            // Error images of the automatic size: the smooth image, the gather at 1 spp
            // without edge supersampling, and the default.
            const std::size_t which = std::size_t(&setting - kImageSettings);
            if (divisor == 1 && (which <= 1 || which == kDefaultImage)) {
                const std::string errorPath =
                    stemPath(csvPath,
                             which == kDefaultImage
                                 ? std::string(".error-default.png")
                                 : concat(".error-gather-", gatherModeName(mode), ".png"));
                const std::vector<uint8_t> pixels =
                    errorImageRgb8(*rendered, reference.xyz, *mask, 0.1);
                if (auto written = writePng(errorPath, size, size, pixels); !written)
                    logWarning(written.error().message);
            }
        }
    }

    // Files: CSV, the reference image, the chart.
    {
        std::ofstream out(csvPath);
        out << "# daisy bench " << options.scenePath << " --reference path --reference-spp " << spp
            << (bench.quick ? " --quick" : "") << "; reference noise " << reference.noise << "\n";
        out << "kind,setting,seconds,patches,rms_y,rms_y_raw,mean_de76,mean_de2000,p95_de2000\n";
        for (const Row& row : rows) {
            out << row.kind << ',' << '"' << row.label << '"' << ',' << row.seconds << ','
                << row.patches << ',' << row.error.relativeRmsYDenoised << ','
                << row.error.relativeRmsY << ',' << row.error.meanDeltaE76 << ','
                << row.error.meanDeltaE2000 << ',' << row.error.p95DeltaE2000 << '\n';
        }
        if (!out) {
            logError(concat(csvPath, ": write failed"));
            return 1;
        }
    }
    if (auto written = writePng(stemPath(csvPath, ".reference.png"), size, size,
                                toSrgb8(xyzToLinearSrgb(reference.xyz, exposure)));
        !written) {
        logWarning(written.error().message);
    }
    ChartSpec chart;
    chart.title = concat(stem, ": image error against time, against the path-traced reference");
    chart.xLabel = "run time (s)";
    chart.yLabel = "relative RMS luminance error (%)";
    chart.referenceY = 100 * kTargetError;
    chart.referenceLabel = "target 2%";
    chart.seriesNames = {"path tracer", "radiosity", "+ direct gather", "+ edge AA",
                         "+ near field"};
    for (const Row& row : rows) {
        const int series = row.kind == "path"                      ? 0
            : row.label.find("gather near") != std::string::npos   ? 4
            : row.label.find("at edges") != std::string::npos      ? 3
            : row.label.find("gather direct") != std::string::npos ? 2
                                                                   : 1;
        chart.points.push_back(
            {row.seconds, std::max(100 * row.error.relativeRmsYDenoised, 1e-3), series, row.label});
    }
    std::vector<ChartPoint> radiosityPoints;
    std::vector<int> radiosityIndex;
    for (std::size_t i = 0; i < chart.points.size(); ++i) {
        if (chart.points[i].series == 0) continue;
        radiosityPoints.push_back(chart.points[i]);
        radiosityIndex.push_back(int(i));
    }
    for (const int i : paretoFront(radiosityPoints))
        chart.front.push_back(radiosityIndex[std::size_t(i)]);
    const Rgb8Image plot = drawLogLogChart(chart);
    if (auto written = writePng(stemPath(csvPath, ".png"), plot.width, plot.height, plot.pixels);
        !written) {
        logWarning(written.error().message);
    }

    bool extrapolated = false;
    const double pathTo2 = pathTimeTo(rows, kTargetError, extrapolated);
    logInfo(concat("bench: wrote ", csvPath, "; the path tracer reaches ",
                   formatNumber(100 * kTargetError), "% in ", formatNumber(pathTo2, 3), " s",
                   extrapolated ? " (extrapolated from its last row as 1 / sqrt(time))" : "",
                   "; 1/20 of that is ", formatNumber(pathTo2 / 20, 3), " s"));
    return 0;
}

}  // namespace daisy::app
