// The settings sweep (bench/sweep.h): each row's run of the pipeline, the reference and its disk
// cache, and the list of rows. The errors are measured in sweep_measure.cpp, the CSV and chart
// made in sweep_report.cpp.
#include "bench/sweep.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include "bench/sweep_measure.h"
#include "core/atomic_file.h"
#include "core/cache_file.h"
#include "core/log.h"
#include "core/memory.h"
#include "core/strings.h"
#include "core/timer.h"
#include "geometry/auto_patch_size.h"
#include "image/camera.h"
#include "image/exposure.h"
#include "image/image_io.h"
#include "image/renderer.h"
#include "pipeline/backend_registry.h"
#include "radiosity/radiosity_system.h"
#include "scene/load_scene.h"
#include "spectral/wavelength_set.h"
#include "spectral/wavelength_spec.h"

namespace daisy {

using sweep::Solution;

namespace {

// Image size of every row's render: large enough for a stable mean CIEDE2000, small enough that
// shading never dominates a row's time.
constexpr int kImageWidth = 320;
constexpr int kImageHeight = 240;
constexpr int kQuickImageWidth = 96;
constexpr int kQuickImageHeight = 72;

// The reference's cache file (core/cache_file.h): detail = 1 for the analytic furnace answer,
// counts = m wavelengths and n patches; payload: the wavelengths, B, the image size, its XYZ,
// the exposure scale and the reference's seconds.
const CacheFileFormat kReferenceFormat{
    {'D', 'A', 'I', 'S', 'Y', 'R', 'F', 'S'}, 1, "bench reference cache file"};

}  // namespace

struct SettingsSweep::State {
    SweepOptions options;
    Scene scene;
    SceneSpectralFacts facts;
    Camera camera;
    int width = 0, height = 0;
    double defaultMaxEdge = 0;
    double referenceMaxEdge = 0;
    Solution reference;
    bool analytic = false;
    double exposureScale = 1;
    double referenceSeconds = 0;

    const SessionSettings& base() const { return options.session; }

    // Runs the pipeline with `setting`; fills the timings of `row` and returns the solution.
    Expected<Solution> run(const SweepSetting& setting, SweepRow& row, bool isReference) {
        resetPeakResidentBytes();
        const Timer total;

        // Every row builds its own F (no disk cache): its time is what the row measures.
        SessionSettings settings = setting.session;
        settings.defaultPatchSize = PatchSizeDefault::InputTriangles;
        settings.subdivideMaxEdge = setting.maxEdge.value_or(defaultMaxEdge);
        settings.cacheDirectory.reset();
        settings.formFactors.progress = false;
        settings.logStages = false;
        if (isReference) {
            settings.wavelengthSet =
                withUvExcitation(fineWavelengths(), facts.hasUvLights, facts.hasFluorescence);
        }
        const int threads = settings.formFactors.threads;
        auto session = Session::fromScene(scene, std::move(settings));
        if (!session) return session.error();
        row.meshSeconds = session->timings().meshSeconds;

        std::optional<std::vector<double>> exact;
        if (isReference) exact = furnaceSolution(session->patches(), session->system());
        if (exact) {
            analytic = true;
            session->setSolution(std::move(*exact));
            row.converged = true;
        } else {
            auto formFactors = session->buildFormFactors();
            if (!formFactors) return formFactors.error();
            row.formFactorSeconds = formFactors->seconds;
            row.nonzeros = session->transport().stats().entries;
            auto solved = session->solve();
            if (!solved) return solved.error();
            row.solveSeconds = session->timings().solveSeconds;
            row.iterations = solved->iterations;
            row.residual = solved->residual;
            row.converged = solved->converged;
        }
        Solution solution{
            session->patches(), session->wavelengths(), session->solution().radiosity, {}};

        Timer stage;
        auto image = renderXyz(solution.patches, session->cornerChannels(false), threads);
        if (!image) return image.error();
        solution.xyz = std::move(*image);
        row.renderSeconds = stage.seconds();
        row.totalSeconds = total.seconds();
        row.peakBytes = peakResidentBytes();
        return solution;
    }

    // The reference's patches: twice as many as the default row's (and at least twice the
    // automatic budget), so every row but the doubled budget is coarser than the reference and
    // meshing error counts as error.
    uint64_t referencePatchBudget(const PatchMesh& defaultPatches) const {
        return 2 *
            std::max<uint64_t>(
                   {kAutoPatchBudget, scene.mesh.triangleCount(), defaultPatches.patchCount()});
    }

    // The radiance XYZ image of the session's smoothed corner values (X, Y, Z, coverage).
    Expected<Image> renderXyz(const PatchMesh& patches, const std::vector<float>& corners,
                              int threads) const {
        RenderSettings settings;
        settings.width = width;
        settings.height = height;
        settings.threads = threads;
        const float background[4] = {0, 0, 0, 0};
        auto image = renderCornerValues(patches, camera, settings, corners, 4, background);
        if (!image) return image.error();
        Image xyz(image->width, image->height, 3);
        for (std::size_t p = 0; p < std::size_t(xyz.width) * xyz.height; ++p)
            for (int c = 0; c < 3; ++c)
                xyz.pixels[p * 3 + c] = image->pixels[p * 4 + c];
        return xyz;
    }

    // FNV-1a 128 of the scene file's bytes and everything the reference depends on.
    Hash128 referenceKey() const {
        Fnv1a128 hash;
        std::ifstream file(scene.path, std::ios::binary);
        hash.updateText(std::string(std::istreambuf_iterator<char>(file), {}));
        const char* convention =
            base().load.mtlConvention == MtlConvention::DaisyRiot ? "daisyriot" : "standard";
        hash.updateText(concat("v1 L", kSweepReferenceLevel, " K", kSweepReferenceRays, " tol",
                               kSweepReferenceTolerance, " seed", base().formFactors.seed, " edge",
                               formatNumber(referenceMaxEdge, 17), " ", width, "x", height, " ",
                               convention, " ", base().load.materialsPath));
        return hash.digest();
    }

    bool readReference(const std::string& path, const Hash128& key);
    Expected<void> writeReference(const std::string& path, const Hash128& key) const;
};

bool SettingsSweep::State::readReference(const std::string& path, const Hash128& key) {
    CacheFileReader in = CacheFileReader::open(path, kReferenceFormat, key);
    if (in.status() != CacheFileReader::Status::Open) return false;
    const uint64_t m = in.header().counts[0], n = in.header().counts[1];
    if (m == 0 || m > 100000) return false;
    auto patches = buildPatchMesh(scene.mesh, referenceMaxEdge);
    if (!patches || n != patches->patchCount()) return false;
    std::vector<double> wavelengths, radiosity;
    int32_t w = 0, h = 0;
    if (!in.readArray(wavelengths, m) || !in.readArray(radiosity, n * m) || !in.read(&w, 4) ||
        !in.read(&h, 4) || w != width || h != height)
        return false;
    Image xyz(w, h, 3);
    double scale = 0, seconds = 0;
    if (!in.read(xyz.pixels.data(), xyz.pixels.size() * sizeof(float)) || !in.read(&scale, 8) ||
        !in.read(&seconds, 8) || !in.finish().empty())
        return false;
    auto set = WavelengthSet::fromWavelengths(wavelengths, "fine+uv");
    if (!set) return false;
    reference =
        Solution{std::move(*patches), std::move(*set), std::move(radiosity), std::move(xyz)};
    analytic = in.header().detail & 1;
    exposureScale = scale;
    referenceSeconds = seconds;
    return true;
}

Expected<void> SettingsSweep::State::writeReference(const std::string& path,
                                                    const Hash128& key) const {
    CacheFileHeader header;
    header.magic = kReferenceFormat.magic;
    header.version = kReferenceFormat.version;
    header.detail = analytic ? 1 : 0;
    header.key = key;
    header.counts = {reference.set.size(), reference.patches.patchCount()};
    const int32_t w = reference.xyz.width, h = reference.xyz.height;
    const std::span<const std::byte> payload[] = {bytesOf(reference.set.wavelengthsNm()),
                                                  bytesOf(reference.radiosity),
                                                  bytesOf(w),
                                                  bytesOf(h),
                                                  bytesOf(reference.xyz.pixels),
                                                  bytesOf(exposureScale),
                                                  bytesOf(referenceSeconds)};
    return writeCacheFile(path, header, payload);
}

SettingsSweep::SettingsSweep(std::unique_ptr<State> state) : state_(std::move(state)) {}
SettingsSweep::SettingsSweep(SettingsSweep&&) noexcept = default;
SettingsSweep& SettingsSweep::operator=(SettingsSweep&&) noexcept = default;
SettingsSweep::~SettingsSweep() = default;

Expected<SettingsSweep> SettingsSweep::open(const SweepOptions& options) {
    auto state = std::make_unique<State>();
    state->options = options;
    auto scene = loadScene(options.session.scenePath, options.session.load);
    if (!scene) return scene.error();
    for (const std::string& warning : scene->warnings)
        logWarning(warning);
    state->scene = std::move(*scene);
    State& s = *state;
    s.width = options.quick ? kQuickImageWidth : kImageWidth;
    s.height = options.quick ? kQuickImageHeight : kImageHeight;
    auto facts = sceneSpectralFacts(s.scene);
    if (!facts) return facts.error();
    s.facts = *facts;
    auto camera = chooseCamera(s.scene, "", double(s.width) / s.height);
    if (!camera) return camera.error();
    s.camera = *camera;
    s.defaultMaxEdge = options.session.subdivideMaxEdge ? *options.session.subdivideMaxEdge
                                                        : chooseAutoPatchSize(s.scene.mesh).maxEdge;
    auto defaultPatches = buildPatchMesh(s.scene.mesh, s.defaultMaxEdge);
    if (!defaultPatches) return Error{concat(s.scene.path, ": ", defaultPatches.error().message)};
    s.referenceMaxEdge =
        chooseAutoPatchSize(s.scene.mesh, s.referencePatchBudget(*defaultPatches)).maxEdge;
    return SettingsSweep(std::move(state));
}

Expected<SweepReference> SettingsSweep::reference(const std::string& cachePath) {
    State& s = *state_;
    SweepReference result;
    const Hash128 key = s.referenceKey();
    result.fromCache = s.readReference(cachePath, key);
    if (result.fromCache) {
        logInfo(concat("bench: reference read from ", cachePath));
    } else {
        SweepSetting setting{"reference", "reference", s.base(), s.referenceMaxEdge};
        setting.session.formFactors.method = FormFactorMethod::Hybrid;
        setting.session.formFactors.quadratureLevel = kSweepReferenceLevel;
        setting.session.formFactors.raysPerPair = kSweepReferenceRays;
        setting.session.solver.tolerance = kSweepReferenceTolerance;
        setting.session.solver.maxIterations = kSweepReferenceMaxIterations;
        setting.session.backend = "cpu";
        logInfo(concat("bench: computing the reference (hybrid L=", kSweepReferenceLevel,
                       ", K=", kSweepReferenceRays, ", fine wavelengths with UV, tolerance ",
                       formatNumber(kSweepReferenceTolerance), "); cached in ", cachePath));
        SweepRow row;
        auto solution = s.run(setting, row, /*isReference=*/true);
        if (!solution) return solution.error();
        if (!row.converged)
            return Error{concat(s.scene.path, ": the reference solve did not converge")};
        s.reference = std::move(*solution);
        s.referenceSeconds = row.totalSeconds;
        s.exposureScale = autoExposureScale(s.reference.xyz);
        if (auto written = s.writeReference(cachePath, key); !written) return written.error();
    }
    result.analytic = s.analytic;
    result.patches = s.reference.patches.patchCount();
    result.samples = s.reference.set.size();
    result.seconds = s.referenceSeconds;
    return result;
}

SweepRow SettingsSweep::run(const SweepSetting& setting) {
    const SessionSettings& o = setting.session;
    SweepRow row;
    row.axis = setting.axis;
    row.label = setting.label;
    row.method = formFactorMethodName(o.formFactors.method);
    row.quadratureLevel = o.formFactors.quadratureLevel;
    row.raysPerPair = o.formFactors.raysPerPair;
    row.backend = o.backend;
    row.wavelengths = o.wavelengthsText;
    row.tolerance = o.solver.tolerance;
    auto solution = state_->run(setting, row, /*isReference=*/false);
    if (!solution) {
        row.error = solution.error().message;
        return row;
    }
    sweep::measure(*solution, state_->reference, state_->exposureScale, row);
    row.patches = solution->patches.patchCount();
    row.samples = solution->set.size();
    return row;
}

Expected<void> SettingsSweep::writeFiles(const SweepFiles& files,
                                         const std::vector<SweepRow>& rows) const {
    const std::string stem =
        std::filesystem::path(state_->options.session.scenePath).stem().string();
    const std::string csv = sweepCsv(stem, rows);
    auto written = writeFileAtomically(files.csv, [&](std::FILE* f) -> std::string {
        std::fputs(csv.c_str(), f);
        return "";
    });
    if (!written) return written;
    const Rgb8Image plot = drawLogLogChart(sweepChart(stem, rows));
    written = writePng(files.chart, plot.width, plot.height, plot.pixels);
    if (!written) return written;
    const Image rgb = xyzToLinearSrgb(state_->reference.xyz, state_->exposureScale);
    return writePng(files.referenceImage, rgb.width, rgb.height, toSrgb8(rgb));
}

std::vector<SweepSetting> SettingsSweep::settings() const {
    const State& state = *state_;
    const SessionSettings& base = state.base();
    std::vector<SweepSetting> rows;
    const auto add = [&](const std::string& axis, const std::string& label, auto change) {
        SweepSetting s{axis, label, base, std::nullopt};
        change(s);
        rows.push_back(std::move(s));
    };
    const bool quick = state.options.quick;
    add("default", "default", [](SweepSetting&) {});
    for (const char* method : {"riemann", "nusselt", "stochastic"}) {
        if (formFactorMethodName(base.formFactors.method) == std::string(method) ||
            (quick && std::string(method) != "riemann"))
            continue;
        add("method", method,
            [&](SweepSetting& s) { parseFormFactorMethod(method, s.session.formFactors.method); });
    }
    if (base.formFactors.method == FormFactorMethod::Hybrid ||
        base.formFactors.method == FormFactorMethod::Riemann) {
        for (int level : {0, 1, 2}) {
            if (level == base.formFactors.quadratureLevel || (quick && level != 0)) continue;
            add("quadrature", concat("L=", level),
                [&](SweepSetting& s) { s.session.formFactors.quadratureLevel = level; });
        }
    }
    for (int rays : {0, 4, 16, 64}) {
        if (rays == base.formFactors.raysPerPair || (quick && rays != 4)) continue;
        add("rays", concat("K=", rays),
            [&](SweepSetting& s) { s.session.formFactors.raysPerPair = rays; });
    }
    if (!base.subdivideMaxEdge) {
        const uint64_t triangles = state.scene.mesh.triangleCount();
        const uint64_t budget = std::max<uint64_t>(kAutoPatchBudget, triangles);
        for (double factor : {0.5, 2.0}) {
            if (quick && factor != 0.5) continue;
            const uint64_t b = uint64_t(double(budget) * factor);
            const double maxEdge = chooseAutoPatchSize(state.scene.mesh, b).maxEdge;
            if (maxEdge == state.defaultMaxEdge) continue;
            add("subdivision", concat("budget ", b, " patches"),
                [&](SweepSetting& s) { s.maxEdge = maxEdge; });
        }
    }
    // Sample densities (each with the UV excitation samples when the scene needs them, as on
    // the command line); `auto` is 400:700:10.
    const std::string baseSet =
        base.wavelengthsText == "auto" ? "400:700:10" : base.wavelengthsText;
    for (const char* set : {"daisyriot", "meyer4", "visible", "400:700:10", "fine"}) {
        if (baseSet == set || (quick && std::string(set) != "daisyriot")) continue;
        add("wavelengths", set, [&](SweepSetting& s) {
            s.session.wavelengthsText = set;
            s.session.wavelengths = *parseWavelengthSpec(set);
        });
    }
    for (double tolerance : {1e-2, 1e-3, 1e-4, 1e-5}) {
        if (tolerance == base.solver.tolerance || (quick && tolerance != 1e-2)) continue;
        add("tolerance", concat("tol=", formatNumber(tolerance)),
            [&](SweepSetting& s) { s.session.solver.tolerance = tolerance; });
    }
    // The backend the default row ran on (`auto` resolves to one of the others).
    const std::string defaultBackend = resolveBackendName(base.backend);
    for (const std::string& backend : backendNames()) {
        if (backend == "auto" || backend == defaultBackend || quick) continue;
        if (!makeBackend(backend, backendOptionsOf(base))) continue;  // not available here
        add("backend", backend, [&](SweepSetting& s) { s.session.backend = backend; });
    }
    return rows;
}

}  // namespace daisy
