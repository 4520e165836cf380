// The bench against the path-traced reference (bench/path_bench.h): the session and camera,
// the reference's chunks (path_reference.h holds their cache), the rows and the files.
#include "bench/path_bench.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bench/chart.h"
#include "bench/path_reference.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/strings.h"
#include "core/timer.h"
#include "image/camera.h"
#include "image/exposure.h"
#include "image/image_io.h"
#include "image/radiosity_image.h"
#include "pathtrace/path_tracer.h"

namespace daisy {

using pathbench::Reference;

namespace {

constexpr uint32_t kReferenceSeed = 1000;  // chunk c's seed is kReferenceSeed + c
constexpr int kChunkSpp = 1024;
constexpr int kQuickChunkSpp = 32;  // quick: at most 64 spp, in chunks of 32
constexpr uint32_t kCurveSeed = 7;
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

std::string stemPath(const std::string& csvPath, const std::string& suffix) {
    std::filesystem::path p(csvPath);
    return (p.parent_path() / (p.stem().string() + suffix)).string();
}

}  // namespace

PathBenchFiles pathBenchFiles(const std::string& scenePath, const std::string& outputPath,
                              const std::string& cacheDir) {
    const std::string stem = std::filesystem::path(scenePath).stem().string();
    PathBenchFiles files;
    files.csv = outputPath.empty() ? concat("bench-path-", stem, ".csv") : outputPath;
    files.chart = stemPath(files.csv, ".png");
    files.referenceImage = stemPath(files.csv, ".reference.png");
    files.referenceCache = cacheDir.empty()
        ? stemPath(files.csv, ".path-reference.bin")
        : (std::filesystem::path(cacheDir) / (stem + ".path-reference.bin")).string();
    return files;
}

std::string PathBenchFiles::errorImage(const std::string& which) const {
    return stemPath(csv, concat(".error-", which, ".png"));
}

struct PathBench::State {
    PathBenchOptions options;
    SessionSettings base;  // options.session without the cache and the stage lines
    int size = 0;  // image width and height
    Camera camera;
    std::optional<Session> first;  // the automatic size's session (the scene, E, patches)
    double autoEdge = 0;  // the finer rows' edge is autoEdge / 1.5 and / 2
    std::vector<uint8_t> mask;
    Reference reference;
    int spp = 0;
    double exposure = 1;
};

PathBench::PathBench(std::unique_ptr<State> state) : state_(std::move(state)) {}
PathBench::PathBench(PathBench&&) noexcept = default;
PathBench& PathBench::operator=(PathBench&&) noexcept = default;
PathBench::~PathBench() = default;

Expected<PathBench> PathBench::open(const PathBenchOptions& options) {
    auto state = std::make_unique<State>();
    State& s = *state;
    s.options = options;
    s.size = options.quick ? 48 : 256;
    s.base = options.session;
    s.base.cacheDirectory.reset();  // every row builds its own F: honest times
    s.base.logStages = false;
    const auto chooseCameraFor = [&](const Scene& scene) -> Expected<void> {
        auto chosen = chooseCamera(scene, "", 1.0);
        if (!chosen) return chosen.error();
        s.camera = *chosen;
        s.camera.aspectRatio = 0;
        return {};
    };
    auto first = Session::open(s.base, chooseCameraFor);
    if (!first) return first.error();
    s.first.emplace(std::move(*first));
    return PathBench(std::move(state));
}

Expected<void> PathBench::prepare() {
    State& s = *state_;
    // The finer rows' edge: the automatic patch size, or where that keeps the input triangles
    // (0), the median triangle's longest edge.
    s.autoEdge = s.first->patchMaxEdge();
    if (s.autoEdge == 0) {
        const PatchMesh& patches = s.first->patches();
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
        s.autoEdge = longest.empty() ? 0.0 : *middle;
    }
    auto mask = emitterMask(s.first->patches(), s.first->system(), s.camera, s.size, s.size);
    if (!mask) return Error{concat(s.options.session.scenePath, ": ", mask.error().message)};
    s.mask = std::move(*mask);
    return {};
}

Expected<PathReferenceSummary> PathBench::reference(const std::string& cachePath) {
    State& s = *state_;
    const PathBenchOptions& options = s.options;
    const int size = s.size;
    Reference& reference = s.reference;
    // Chunks until referenceSpp (rounded up to whole chunks) or, with referenceNoisePercent,
    // until its noise is under that; resumed from and saved to the cache.
    const int total = options.quick ? std::min(options.referenceSpp, 64) : options.referenceSpp;
    const int chunkSpp = std::min(total, options.quick ? kQuickChunkSpp : kChunkSpp);
    const int chunks = (total + chunkSpp - 1) / chunkSpp;
    const double noiseTarget = options.referenceNoisePercent / 100;
    const Hash128 key = pathbench::referenceKey(
        options.session.scenePath,
        concat(size, " ", chunkSpp, " ", kReferenceSeed, " ", s.first->wavelengths().name(), " ",
               s.first->wavelengths().size()));
    if (pathbench::readReference(cachePath, key, size, size, reference)) {
        pathbench::finishReference(reference, size, size, s.mask);
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
            noiseTarget > 0
                ? concat(", until its noise is under ", options.referenceNoisePercent, "%")
                : std::string(),
            "); saved after each chunk in ", cachePath));
    }
    while (!converged()) {
        PathTraceSettings settings;
        settings.width = settings.height = size;
        settings.samplesPerPixel = chunkSpp;
        settings.seed = kReferenceSeed + uint32_t(reference.chunks);
        settings.threads = options.session.formFactors.threads;
        auto traced = pathTrace(s.first->scene(), s.first->wavelengths(), s.camera, settings);
        if (!traced) return Error{concat(options.session.scenePath, ": ", traced.error().message)};
        for (std::size_t p = 0; p < std::size_t(size) * size; ++p) {
            for (int c = 0; c < 3; ++c)
                reference.xyzSum[p * 3 + c] += traced->image.pixels[p * traced->image.channels + c];
            reference.varianceSum[p] += traced->varianceY.pixels[p];
        }
        ++reference.chunks;
        reference.seconds += traced->seconds;
        pathbench::finishReference(reference, size, size, s.mask);
        if (auto written = pathbench::writeReference(cachePath, key, size, size, reference);
            !written)
            logWarning(concat("bench: ", written.error().message));
        const int left = chunks - reference.chunks;
        logInfo(concat("bench: reference chunk ", reference.chunks, " of ", chunks, " (seed ",
                       settings.seed, "): ", formatNumber(traced->seconds, 3), " s, noise ",
                       formatNumber(100 * reference.noise, 3), "%",
                       left > 0
                           ? concat(", at most ", formatDuration(left * traced->seconds), " to go")
                           : std::string()));
    }
    s.spp = reference.chunks * chunkSpp;
    s.exposure = autoExposureScale(reference.xyz);
    return PathReferenceSummary{s.spp, reference.seconds, reference.noise};
}

Expected<void> PathBench::runPathRows(std::vector<PathBenchRow>& rows,
                                      const std::function<void(const PathBenchRow&)>& onRow) {
    const State& s = *state_;
    const std::vector<int> curve =
        s.options.quick ? std::vector<int>{1, 4} : std::vector<int>{1, 4, 16, 64, 256};
    for (const int n : curve) {
        PathTraceSettings settings;
        settings.width = settings.height = s.size;
        settings.samplesPerPixel = n;
        settings.seed = kCurveSeed;
        settings.threads = s.options.session.formFactors.threads;
        settings.showProgress = false;
        auto traced = pathTrace(s.first->scene(), s.first->wavelengths(), s.camera, settings);
        if (!traced)
            return Error{concat(s.options.session.scenePath, ": ", traced.error().message)};
        PathBenchRow row{"path", concat(n, " spp"), traced->seconds, 0, {}};
        row.error = compareImages(traced->image, s.reference.xyz, s.mask, s.exposure,
                                  &s.reference.varianceY);
        onRow(row);
        rows.push_back(row);
    }
    return {};
}

Expected<void> PathBench::runRadiosityRows(const PathBenchFiles& files,
                                           std::vector<PathBenchRow>& rows,
                                           const std::function<void(const PathBenchRow&)>& onRow) {
    const State& s = *state_;
    const std::string& scenePath = s.options.session.scenePath;
    RenderSettings image;
    image.width = image.height = s.size;
    image.threads = s.options.session.formFactors.threads;
    const std::vector<double> divisors =
        s.options.quick ? std::vector<double>{1} : std::vector<double>{1, 1.5, 2};
    for (const double divisor : divisors) {
        const Timer timer;
        SessionSettings settings = s.base;
        settings.subdivideMaxEdge = divisor == 1 ? s.first->patchMaxEdge() : s.autoEdge / divisor;
        auto session = Session::open(settings);
        if (!session) return session.error();
        const std::string size = divisor == 1 ? std::string("auto") : concat("edge/", divisor);
        // An all-pairs F over --max-memory: one "refused" row (the finer sizes would need
        // more), and the path tracer's rows still stand.
        if (const uint64_t bytes = session->matrixEstimate().matrixBytes;
            bytes > settings.maxMemoryBytes) {
            PathBenchRow row{
                "refused",
                concat(size, ": F needs about ", formatBytes(double(bytes)),
                       ", more than --max-memory ", formatBytes(double(settings.maxMemoryBytes))),
                0,
                session->patches().patchCount(),
                {}};
            onRow(row);
            rows.push_back(row);
            break;
        }
        if (auto f = session->buildFormFactors(); !f) return f.error();
        if (auto solved = session->solve(); !solved) return solved.error();
        const double pipelineSeconds = timer.seconds();
        for (const ImageSetting& setting : kImageSettings) {
            const auto [mode, samples, edgeSamples] = setting;
            const Timer imageTimer;
            DirectLightSettings direct;
            direct.seed = static_cast<uint32_t>(s.options.session.formFactors.seed);
            image.samplesPerPixel = samples;
            image.edgeSamplesPerPixel = edgeSamples;
            auto rendered = renderRadiosityImage(*session, s.camera, image, mode, direct, false);
            if (!rendered) return Error{concat(scenePath, ": ", rendered.error().message)};
            PathBenchRow row{"radiosity",
                             concat(size, ", gather ", gatherModeName(mode), ", ", samples, " spp",
                                    edgeSamples > 0 ? concat(" (", edgeSamples, " at edges)") : ""),
                             pipelineSeconds + imageTimer.seconds(),
                             session->patches().patchCount(),
                             {}};
            row.error = compareImages(*rendered, s.reference.xyz, s.mask, s.exposure,
                                      &s.reference.varianceY);
            onRow(row);
            rows.push_back(row);
            // Error images of the automatic size: the smooth image, the gather at 1 spp
            // without edge supersampling, and the default.
            const std::size_t which = std::size_t(&setting - kImageSettings);
            if (divisor == 1 && (which <= 1 || which == kDefaultImage)) {
                const std::string errorPath = files.errorImage(
                    which == kDefaultImage ? std::string("default")
                                           : concat("gather-", gatherModeName(mode)));
                const std::vector<uint8_t> pixels =
                    errorImageRgb8(*rendered, s.reference.xyz, s.mask, 0.1);
                if (auto written = writePng(errorPath, s.size, s.size, pixels); !written)
                    logWarning(written.error().message);
            }
        }
    }
    return {};
}

Expected<void> PathBench::writeFiles(const PathBenchFiles& files,
                                     const std::vector<PathBenchRow>& rows) const {
    const State& s = *state_;
    {
        std::ofstream out(files.csv);
        out << "# daisy bench " << s.options.session.scenePath
            << " --reference path --reference-spp " << s.spp << (s.options.quick ? " --quick" : "")
            << "; reference noise " << s.reference.noise << "\n";
        out << "kind,setting,seconds,patches,rms_y,rms_y_raw,mean_de76,mean_de2000,p95_de2000\n";
        for (const PathBenchRow& row : rows) {
            out << row.kind << ',' << '"' << row.label << '"' << ',';
            if (row.kind == "refused") {
                out << ',' << row.patches << ",,,,,\n";  // no run, no image
                continue;
            }
            out << row.seconds << ',' << row.patches << ',' << row.error.relativeRmsYDenoised << ','
                << row.error.relativeRmsY << ',' << row.error.meanDeltaE76 << ','
                << row.error.meanDeltaE2000 << ',' << row.error.p95DeltaE2000 << '\n';
        }
        if (!out) return Error{concat(files.csv, ": write failed")};
    }
    if (auto written = writePng(files.referenceImage, s.size, s.size,
                                toSrgb8(xyzToLinearSrgb(s.reference.xyz, s.exposure)));
        !written) {
        logWarning(written.error().message);
    }
    const std::string stem = std::filesystem::path(s.options.session.scenePath).stem().string();
    ChartSpec chart;
    chart.title = concat(stem, ": image error against time, against the path-traced reference");
    chart.xLabel = "run time (s)";
    chart.yLabel = "relative RMS luminance error (%)";
    chart.referenceY = 100 * kPathBenchTargetError;
    chart.referenceLabel = "target 2%";
    chart.seriesNames = {"path tracer", "radiosity", "+ direct gather", "+ edge AA",
                         "+ near field"};
    for (const PathBenchRow& row : rows) {
        if (row.kind == "refused") continue;
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
    if (auto written = writePng(files.chart, plot.width, plot.height, plot.pixels); !written)
        logWarning(written.error().message);
    return {};
}

double pathTimeTo(const std::vector<PathBenchRow>& rows, double target, bool& extrapolated) {
    const PathBenchRow* previous = nullptr;
    extrapolated = false;
    for (const PathBenchRow& row : rows) {
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

}  // namespace daisy
