#include "app/bench_sweep.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "app/session_options.h"
#include "bench/chart.h"
#include "core/atomic_file.h"
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
#include "radiosity/solver.h"
#include "spectral/color.h"
#include "spectral/wavelength_set.h"

namespace daisy::app {
namespace {

// Image size of every row's render: large enough for a stable mean CIEDE2000, small enough that
// shading never dominates a row's time.
constexpr int kImageWidth = 320;
constexpr int kImageHeight = 240;
constexpr int kQuickImageWidth = 96;
constexpr int kQuickImageHeight = 72;

// The reference: the accurate method at high settings, converged far below the JND.
constexpr int kReferenceLevel = 2;
constexpr int kReferenceRays = 64;
constexpr double kReferenceTolerance = 1e-6;
constexpr int kReferenceMaxIterations = 100000;

struct SweepSetting {
    std::string axis;  // "default", "method", "quadrature", ...
    std::string label;  // what differs from the default, e.g. "K=64"
    CommonOptions options;
    std::optional<double> maxEdge;  // the patch size, when not the default row's
};

// What one run of the pipeline produced.
struct Solution {
    PatchMesh patches;
    WavelengthSet set;
    std::vector<double> radiosity;  // n x m
    Image xyz;  // radiance XYZ per pixel
};

struct RowResult {
    std::string error;  // non-empty: the row failed with this message
    double meshSeconds = 0, formFactorSeconds = 0, solveSeconds = 0, renderSeconds = 0;
    double totalSeconds = 0;
    uint64_t peakBytes = 0;
    uint64_t nonzeros = 0;
    int iterations = 0;
    double residual = 0;
    bool converged = false;
    double relativeRmsB = NAN, relativeRmsY = NAN;
    std::string errorLevel;  // "patch" or "triangle"
    double meanDeltaE = NAN, p95DeltaE = NAN;
    bool pareto = false;
};

// The furnace oracle: a closed mesh (every edge shared by exactly two patches), one diagonal
// (non-fluorescent) material operator and the same emission on every patch give G = B, so
// B = E + rho B, i.e. B = E / (1 - rho) per wavelength, exactly.
std::optional<std::vector<double>> furnaceSolution(const PatchMesh& patches,
                                                   const RadiositySystem& system) {
    if (system.operators.size() != 1 || !system.operators[0].isDiagonal) return std::nullopt;
    const std::size_t n = system.patchCount, m = system.wavelengthCount;
    for (std::size_t i = 1; i < n; ++i)
        if (!std::equal(system.emissionRow(0), system.emissionRow(0) + m, system.emissionRow(i)))
            return std::nullopt;
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (const auto& corners : patches.patches)
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = corners[e], b = corners[(e + 1) % 3];
            ++edges[{std::min(a, b), std::max(a, b)}];
        }
    for (const auto& [edge, count] : edges)
        if (count != 2) return std::nullopt;
    const std::vector<double>& rho = system.operators[0].diagonal;
    std::vector<double> radiosity(n * m);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t k = 0; k < m; ++k) {
            if (rho[k] >= 1) return std::nullopt;
            radiosity[i * m + k] = system.emissionRow(i)[k] / (1 - rho[k]);
        }
    return radiosity;
}

class Sweep {
public:
    Sweep(const CommonOptions& options, const BenchOptions& bench, Scene scene)
        : base_(options), bench_(bench), scene_(std::move(scene)) {
        width_ = bench.quick ? kQuickImageWidth : kImageWidth;
        height_ = bench.quick ? kQuickImageHeight : kImageHeight;
    }

    Expected<void> prepare() {
        auto facts = sceneSpectralFacts(scene_);
        if (!facts) return facts.error();
        facts_ = *facts;
        auto camera = chooseCamera(scene_, "", double(width_) / height_);
        if (!camera) return camera.error();
        camera_ = *camera;
        defaultMaxEdge_ = base_.subdivideMaxEdge ? *base_.subdivideMaxEdge
                                                 : chooseAutoPatchSize(scene_.mesh).maxEdge;
        auto defaultPatches = buildPatchMesh(scene_.mesh, defaultMaxEdge_);
        if (!defaultPatches)
            return Error{concat(scene_.path, ": ", defaultPatches.error().message)};
        referenceMaxEdge_ =
            chooseAutoPatchSize(scene_.mesh, referencePatchBudget(*defaultPatches)).maxEdge;
        return {};
    }

    // Runs the pipeline with `setting`; fills the timings of `row` and returns the solution.
    Expected<Solution> run(const SweepSetting& setting, RowResult& row, bool reference) {
        const CommonOptions& options = setting.options;
        resetPeakResidentBytes();
        const Timer total;

        // Every row builds its own F (no disk cache): its time is what the row measures.
        SessionSettings settings = sessionSettingsFrom(options, PatchSizeDefault::InputTriangles);
        settings.subdivideMaxEdge = setting.maxEdge.value_or(defaultMaxEdge_);
        settings.cacheDirectory.reset();
        settings.formFactors.progress = false;
        settings.logStages = false;
        if (reference) {
            settings.wavelengthSet =
                withUvExcitation(fineWavelengths(), facts_.hasUvLights, facts_.hasFluorescence);
        }
        auto session = Session::fromScene(scene_, std::move(settings));
        if (!session) return session.error();
        row.meshSeconds = session->timings().meshSeconds;

        std::optional<std::vector<double>> exact;
        if (reference) exact = furnaceSolution(session->patches(), session->system());
        if (exact) {
            analytic_ = true;
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
        auto image = renderXyz(solution.patches, session->cornerChannels(false), options.threads);
        if (!image) return image.error();
        solution.xyz = std::move(*image);
        row.renderSeconds = stage.seconds();
        row.totalSeconds = total.seconds();
        row.peakBytes = peakResidentBytes();
        return solution;
    }

    // The reference, from the cache when its key matches, else computed and cached.
    Expected<void> loadOrComputeReference(const std::string& cachePath) {
        const uint64_t key = referenceKey();
        if (readReference(cachePath, key)) {
            logInfo(concat("bench: reference read from ", cachePath));
            return {};
        }
        SweepSetting setting{"reference", "reference", base_, referenceMaxEdge_};
        setting.options.method = "hybrid";
        setting.options.quadratureLevel = kReferenceLevel;
        setting.options.raysPerPair = kReferenceRays;
        setting.options.tolerance = kReferenceTolerance;
        setting.options.maxIterations = kReferenceMaxIterations;
        setting.options.backend = "cpu";
        logInfo(concat("bench: computing the reference (hybrid L=", kReferenceLevel,
                       ", K=", kReferenceRays, ", fine wavelengths with UV, tolerance ",
                       formatNumber(kReferenceTolerance), "); cached in ", cachePath));
        RowResult row;
        auto solution = run(setting, row, /*reference=*/true);
        if (!solution) return solution.error();
        if (!row.converged)
            return Error{concat(scene_.path, ": the reference solve did not converge")};
        reference_ = std::move(*solution);
        referenceSeconds_ = row.totalSeconds;
        exposureScale_ = autoExposureScale(reference_.xyz);
        return writeReference(cachePath, key);
    }

    // Fills the error columns of `row` from `solution` against the reference.
    void measure(const Solution& solution, RowResult& row) const {
        const bool samePatches = solution.patches.patchCount() == reference_.patches.patchCount() &&
            solution.patches.sourceTriangle == reference_.patches.sourceTriangle;
        row.errorLevel = samePatches ? "patch" : "triangle";
        const auto groups = [&](const Solution& s) {
            return samePatches ? groupByPatch(s) : groupBySourceTriangle(s);
        };
        const Groups mine = groups(solution), theirs = groups(reference_);
        const WavelengthSet& set = solution.set;
        const std::size_t m = set.size(), mr = reference_.set.size();
        double diffB = 0, normB = 0, diffY = 0, normY = 0;
        const std::vector<double> projection = projectionOnto(set, reference_.set);
        std::vector<double> resampled(m);
        for (std::size_t g = 0; g < mine.areas.size(); ++g) {
            const double* b = mine.spectra.data() + g * m;
            const double* r = theirs.spectra.data() + g * mr;
            for (std::size_t k = 0; k < m; ++k) {
                resampled[k] = 0;
                for (std::size_t j = 0; j < mr; ++j)
                    resampled[k] += projection[k * mr + j] * r[j];
                if (std::isnan(projection[k * mr])) continue;  // outside the reference's domain
                const double w = mine.areas[g] * set.binWidthNm(k);
                diffB += w * (b[k] - resampled[k]) * (b[k] - resampled[k]);
                normB += w * resampled[k] * resampled[k];
            }
            const double y = set.toXyz(std::span<const double>(b, m))[1];
            const double yr = reference_.set.toXyz(std::span<const double>(r, mr))[1];
            diffY += mine.areas[g] * (y - yr) * (y - yr);
            normY += mine.areas[g] * yr * yr;
        }
        row.relativeRmsB = normB > 0 ? std::sqrt(diffB / normB) : NAN;
        row.relativeRmsY = normY > 0 ? std::sqrt(diffY / normY) : NAN;

        const std::vector<Lab> a = displayedLab(solution.xyz), b = displayedLab(reference_.xyz);
        std::vector<double> deltas(a.size());
        double sum = 0;
        for (std::size_t p = 0; p < a.size(); ++p) {
            deltas[p] = deltaE2000(a[p], b[p]);
            sum += deltas[p];
        }
        row.meanDeltaE = deltas.empty() ? NAN : sum / deltas.size();
        if (!deltas.empty()) {
            const std::size_t at = std::min(deltas.size() - 1, deltas.size() * 95 / 100);
            std::nth_element(deltas.begin(), deltas.begin() + at, deltas.end());
            row.p95DeltaE = deltas[at];
        }
    }

    const Solution& reference() const { return reference_; }
    bool analytic() const { return analytic_; }
    double exposureScale() const { return exposureScale_; }
    double referenceSeconds() const { return referenceSeconds_; }

    std::vector<SweepSetting> settings() const;

private:
    struct Groups {
        std::vector<double> areas;
        std::vector<double> spectra;  // groups x m, area-weighted means
    };

    // The reference's patches: twice as many as the default row's (and at least twice the
    // automatic budget), so every row but the doubled budget is coarser than the reference and
    // meshing error counts as error.
    uint64_t referencePatchBudget(const PatchMesh& defaultPatches) const {
        return 2 *
            std::max<uint64_t>(
                   {kAutoPatchBudget, scene_.mesh.triangleCount(), defaultPatches.patchCount()});
    }

    static Groups groupByPatch(const Solution& s) { return {s.patches.areas, s.radiosity}; }
    static Groups groupBySourceTriangle(const Solution& s) {
        const std::size_t m = s.set.size();
        uint32_t triangles = 0;
        for (uint32_t t : s.patches.sourceTriangle)
            triangles = std::max(triangles, t + 1);
        Groups g{std::vector<double>(triangles, 0.0), std::vector<double>(triangles * m, 0.0)};
        for (std::size_t i = 0; i < s.patches.patchCount(); ++i) {
            const uint32_t t = s.patches.sourceTriangle[i];
            g.areas[t] += s.patches.areas[i];
            for (std::size_t k = 0; k < m; ++k)
                g.spectra[t * m + k] += s.patches.areas[i] * s.radiosity[i * m + k];
        }
        for (uint32_t t = 0; t < triangles; ++t)
            for (std::size_t k = 0; k < m && g.areas[t] > 0; ++k)
                g.spectra[t * m + k] /= g.areas[t];
        return g;
    }
    // The m x mr matrix that samples the reference's spectra on `set` as emission is sampled
    // (spectral/spectrum.h): row k holds the hat-weighted mean of the reference's piecewise-
    // linear reconstruction over set's hat k, integral h_k g_j / integral h_k, both over the
    // reference's domain (numerically, 0.05 nm steps). The identity when the sets are equal. A
    // hat wholly outside the reference's domain (daisyriot's 350 nm against a reference without
    // UV samples) has nothing to compare with: its row is NaN.
    static std::vector<double> projectionOnto(const WavelengthSet& set,
                                              const WavelengthSet& reference) {
        const std::size_t m = set.size(), mr = reference.size();
        std::vector<double> p(m * mr, 0.0);
        if (set.wavelengthsNm() == reference.wavelengthsNm()) {
            for (std::size_t k = 0; k < m; ++k)
                p[k * mr + k] = 1;
            return p;
        }
        constexpr double kStepNm = 0.05;
        for (std::size_t k = 0; k < m; ++k) {
            auto [first, last] = set.hatSupportNm(k);
            first = std::max(first, reference.domainStartNm());
            last = std::min(last, reference.domainEndNm());
            double weight = 0;
            for (double nm = first + kStepNm / 2; nm < last; nm += kStepNm) {
                const double h = set.hat(k, nm);
                weight += h;
                for (std::size_t j = 0; j < mr; ++j)
                    p[k * mr + j] += h * reference.hat(j, nm);
            }
            for (std::size_t j = 0; j < mr; ++j)
                p[k * mr + j] = weight > 0 ? p[k * mr + j] / weight : NAN;
        }
        return p;
    }

    // The radiance XYZ image of the session's smoothed corner values (X, Y, Z, coverage).
    Expected<Image> renderXyz(const PatchMesh& patches, const std::vector<float>& corners,
                              int threads) const {
        RenderSettings settings;
        settings.width = width_;
        settings.height = height_;
        settings.threads = threads;
        const float background[4] = {0, 0, 0, 0};
        auto image = renderCornerValues(patches, camera_, settings, corners, 4, background);
        if (!image) return image.error();
        Image xyz(image->width, image->height, 3);
        for (std::size_t p = 0; p < std::size_t(xyz.width) * xyz.height; ++p)
            for (int c = 0; c < 3; ++c)
                xyz.pixels[p * 3 + c] = image->pixels[p * 4 + c];
        return xyz;
    }

    // Lab of every pixel as displayed: the reference's exposure, 8-bit sRGB, decoded under D65.
    std::vector<Lab> displayedLab(const Image& xyz) const {
        const std::vector<uint8_t> srgb = toSrgb8(xyzToLinearSrgb(xyz, exposureScale_));
        std::vector<Lab> lab(srgb.size() / 3);
        for (std::size_t p = 0; p < lab.size(); ++p)
            lab[p] = srgb8ToLab({srgb[p * 3], srgb[p * 3 + 1], srgb[p * 3 + 2]});
        return lab;
    }

    // FNV-1a 64 of the scene file's bytes and everything the reference depends on.
    uint64_t referenceKey() const {
        uint64_t hash = 14695981039346656037ull;
        const auto mix = [&](const std::string& bytes) {
            for (unsigned char c : bytes)
                hash = (hash ^ c) * 1099511628211ull;
        };
        std::ifstream file(scene_.path, std::ios::binary);
        mix(std::string(std::istreambuf_iterator<char>(file), {}));
        mix(concat("v1 L", kReferenceLevel, " K", kReferenceRays, " tol", kReferenceTolerance,
                   " seed", base_.seed, " edge", formatNumber(referenceMaxEdge_, 17), " ", width_,
                   "x", height_, " ", base_.mtlConvention, " ", base_.materialsPath));
        return hash;
    }

    bool readReference(const std::string& path, uint64_t key);
    Expected<void> writeReference(const std::string& path, uint64_t key) const;

    CommonOptions base_;
    BenchOptions bench_;
    Scene scene_;
    SceneSpectralFacts facts_;
    Camera camera_;
    int width_ = 0, height_ = 0;
    double defaultMaxEdge_ = 0;
    double referenceMaxEdge_ = 0;
    Solution reference_;
    bool analytic_ = false;
    double exposureScale_ = 1;
    double referenceSeconds_ = 0;
};

// Cache layout: magic, key, flags, m wavelengths, n patches, B, image size and XYZ, exposure.
constexpr char kCacheMagic[8] = {'D', 'A', 'I', 'S', 'Y', 'R', 'F', '1'};

bool Sweep::readReference(const std::string& path, uint64_t key) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    char magic[8];
    uint64_t storedKey = 0, m = 0, n = 0, flags = 0;
    int32_t w = 0, h = 0;
    in.read(magic, 8).read(reinterpret_cast<char*>(&storedKey), 8);
    if (!in || !std::equal(magic, magic + 8, kCacheMagic) || storedKey != key) return false;
    in.read(reinterpret_cast<char*>(&flags), 8).read(reinterpret_cast<char*>(&m), 8);
    if (!in || m == 0 || m > 100000) return false;
    std::vector<double> wavelengths(m);
    in.read(reinterpret_cast<char*>(wavelengths.data()), std::streamsize(m * 8));
    in.read(reinterpret_cast<char*>(&n), 8);
    auto patches = buildPatchMesh(scene_.mesh, referenceMaxEdge_);
    if (!in || !patches || n != patches->patchCount()) return false;
    std::vector<double> radiosity(n * m);
    in.read(reinterpret_cast<char*>(radiosity.data()), std::streamsize(n * m * 8));
    in.read(reinterpret_cast<char*>(&w), 4).read(reinterpret_cast<char*>(&h), 4);
    if (!in || w != width_ || h != height_) return false;
    Image xyz(w, h, 3);
    in.read(reinterpret_cast<char*>(xyz.pixels.data()), std::streamsize(xyz.pixels.size() * 4));
    double scale = 0, seconds = 0;
    in.read(reinterpret_cast<char*>(&scale), 8).read(reinterpret_cast<char*>(&seconds), 8);
    auto set = WavelengthSet::fromWavelengths(wavelengths, "fine+uv");
    if (!in || !set) return false;
    reference_ =
        Solution{std::move(*patches), std::move(*set), std::move(radiosity), std::move(xyz)};
    analytic_ = flags & 1;
    exposureScale_ = scale;
    referenceSeconds_ = seconds;
    return true;
}

Expected<void> Sweep::writeReference(const std::string& path, uint64_t key) const {
    return writeFileAtomically(path, [&](std::FILE* f) -> std::string {
        const auto put = [&](const void* data, std::size_t bytes) {
            std::fwrite(data, 1, bytes, f);
        };
        const uint64_t flags = analytic_ ? 1 : 0, m = reference_.set.size(),
                       n = reference_.patches.patchCount();
        const int32_t w = reference_.xyz.width, h = reference_.xyz.height;
        put(kCacheMagic, 8), put(&key, 8), put(&flags, 8), put(&m, 8);
        put(reference_.set.wavelengthsNm().data(), m * 8);
        put(&n, 8), put(reference_.radiosity.data(), n * m * 8);
        put(&w, 4), put(&h, 4), put(reference_.xyz.pixels.data(), reference_.xyz.pixels.size() * 4);
        put(&exposureScale_, 8), put(&referenceSeconds_, 8);
        return "";
    });
}

std::vector<SweepSetting> Sweep::settings() const {
    std::vector<SweepSetting> rows;
    const auto add = [&](const std::string& axis, const std::string& label, auto change) {
        SweepSetting s{axis, label, base_, std::nullopt};
        change(s);
        rows.push_back(std::move(s));
    };
    const bool quick = bench_.quick;
    add("default", "default", [](SweepSetting&) {});
    for (const char* method : {"riemann", "nusselt", "stochastic"}) {
        if (base_.method == method || (quick && std::string(method) != "riemann")) continue;
        add("method", method, [&](SweepSetting& s) { s.options.method = method; });
    }
    if (base_.method == "hybrid" || base_.method == "riemann") {
        for (int level : {0, 1, 2}) {
            if (level == base_.quadratureLevel || (quick && level != 0)) continue;
            add("quadrature", concat("L=", level),
                [&](SweepSetting& s) { s.options.quadratureLevel = level; });
        }
    }
    for (int rays : {0, 4, 16, 64}) {
        if (rays == base_.raysPerPair || (quick && rays != 4)) continue;
        add("rays", concat("K=", rays), [&](SweepSetting& s) { s.options.raysPerPair = rays; });
    }
    if (!base_.subdivideMaxEdge) {
        const uint64_t triangles = scene_.mesh.triangleCount();
        const uint64_t budget = std::max<uint64_t>(kAutoPatchBudget, triangles);
        for (double factor : {0.5, 2.0}) {
            if (quick && factor != 0.5) continue;
            const uint64_t b = uint64_t(double(budget) * factor);
            const double maxEdge = chooseAutoPatchSize(scene_.mesh, b).maxEdge;
            if (maxEdge == defaultMaxEdge_) continue;
            add("subdivision", concat("budget ", b, " patches"),
                [&](SweepSetting& s) { s.maxEdge = maxEdge; });
        }
    }
    // Sample densities (each with the UV excitation samples when the scene needs them, as on
    // the command line); `auto` is 400:700:10.
    const std::string baseSet = base_.wavelengths == "auto" ? "400:700:10" : base_.wavelengths;
    for (const char* set : {"daisyriot", "meyer4", "visible", "400:700:10", "fine"}) {
        if (baseSet == set || (quick && std::string(set) != "daisyriot")) continue;
        add("wavelengths", set, [&](SweepSetting& s) {
            s.options.wavelengths = set;
            s.options.wavelengthSpec = *parseWavelengthSpec(set);
        });
    }
    for (double tolerance : {1e-2, 1e-3, 1e-4, 1e-5}) {
        if (tolerance == base_.tolerance || (quick && tolerance != 1e-2)) continue;
        add("tolerance", concat("tol=", formatNumber(tolerance)),
            [&](SweepSetting& s) { s.options.tolerance = tolerance; });
    }
    // The backend the default row ran on (`auto` resolves to one of the others).
    const std::string defaultBackend = resolveBackendName(base_.backend);
    for (const std::string& backend : backendNames()) {
        if (backend == "auto" || backend == defaultBackend || quick) continue;
        if (!makeBackend(backend, BackendOptions{base_.device})) continue;  // not available here
        add("backend", backend, [&](SweepSetting& s) { s.options.backend = backend; });
    }
    return rows;
}

std::string withExtension(const std::string& path, const std::string& suffix) {
    const std::filesystem::path p(path);
    return (p.parent_path() / p.stem()).string() + suffix;
}

std::string csvNumber(double value) {
    return std::isfinite(value) ? formatNumber(value, 6) : "";
}

}  // namespace

int runSweep(const CommonOptions& options, const BenchOptions& bench) {
    if (options.scenePath.empty()) {
        logError("daisy bench: give a SCENE to sweep, or --stress for the stress suite");
        return 2;
    }
    auto scene = loadScene(options.scenePath, options.sceneLoadOptions());
    if (!scene) {
        logError(scene.error().message);
        return 2;
    }
    for (const std::string& warning : scene->warnings)
        logWarning(warning);
    const std::string stem = std::filesystem::path(options.scenePath).stem().string();
    const std::string csvPath =
        bench.outputPath.empty() ? concat("bench-", stem, ".csv") : bench.outputPath;
    const std::string cachePath = options.cacheDir.empty()
        ? withExtension(csvPath, ".reference.bin")
        : (std::filesystem::path(options.cacheDir) / (stem + ".bench-reference.bin")).string();

    Sweep sweep(options, bench, std::move(*scene));
    if (auto prepared = sweep.prepare(); !prepared) {
        logError(prepared.error().message);
        return 2;
    }
    if (auto reference = sweep.loadOrComputeReference(cachePath); !reference) {
        logError(reference.error().message);
        return 2;
    }
    logInfo(concat("bench: reference is ",
                   sweep.analytic() ? "the analytic furnace solution" : "the converged solution",
                   " (", formatCount(sweep.reference().patches.patchCount()), " patches, ",
                   sweep.reference().set.size(), " wavelengths, ",
                   formatNumber(sweep.referenceSeconds(), 3), " s)"));

    const std::vector<SweepSetting> settings = sweep.settings();
    std::vector<RowResult> rows(settings.size());
    std::vector<uint64_t> patchCounts(settings.size(), 0);
    std::vector<std::size_t> sampleCounts(settings.size(), 0);
    logInfo(
        "  setting                          time s   F s      solve s  peak MB  mean dE00  "
        "rms B     rms Y");
    for (std::size_t r = 0; r < settings.size(); ++r) {
        auto solution = sweep.run(settings[r], rows[r], /*reference=*/false);
        if (!solution) {
            rows[r].error = solution.error().message;
            logWarning(concat("bench: ", settings[r].label, ": ", rows[r].error));
            continue;
        }
        sweep.measure(*solution, rows[r]);
        patchCounts[r] = solution->patches.patchCount();
        sampleCounts[r] = solution->set.size();
        char line[256];
        std::snprintf(
            line, sizeof line, "  %-32s %-8.3f %-8.3f %-8.3f %-8.0f %-10.3f %-9.2e %-9.2e",
            concat(settings[r].axis == "default" ? "" : settings[r].axis + " ", settings[r].label)
                .c_str(),
            rows[r].totalSeconds, rows[r].formFactorSeconds, rows[r].solveSeconds,
            rows[r].peakBytes / 1e6, rows[r].meanDeltaE, rows[r].relativeRmsB,
            rows[r].relativeRmsY);
        logInfo(line);
    }

    ChartSpec chart;
    chart.title = concat(stem, ": image error against run time (daisy bench)");
    chart.xLabel = "run time of the whole pipeline (s)";
    chart.yLabel = "mean CIEDE2000 against the reference";
    chart.referenceY = kJustNoticeableDeltaE;
    chart.referenceLabel = "just noticeable (1)";
    std::vector<std::string> axes;
    for (std::size_t r = 0; r < settings.size(); ++r) {
        auto found = std::find(axes.begin(), axes.end(), settings[r].axis);
        const int series = int(found - axes.begin());
        if (found == axes.end()) axes.push_back(settings[r].axis);
        // A perfect image (mean 0) sits at the bottom of a log axis: floor it at 1e-3.
        ChartPoint point{rows[r].totalSeconds, std::max(rows[r].meanDeltaE, 1e-3), series,
                         settings[r].label};
        if (!rows[r].error.empty()) point.x = NAN;
        chart.points.push_back(point);
    }
    chart.seriesNames = axes;
    chart.front = paretoFront(chart.points);
    for (int k : chart.front)
        rows[k].pareto = true;

    int cheapest = -1;
    for (int k : chart.front)
        if (rows[k].meanDeltaE < kJustNoticeableDeltaE && cheapest < 0) cheapest = k;

    std::string csv =
        "scene,axis,setting,method,quadrature,rays,backend,patches,wavelengths,samples,tolerance,"
        "mesh_s,formfactors_s,solve_s,render_s,total_s,peak_bytes,nonzeros,iterations,residual,"
        "converged,rel_rms_B,rel_rms_Y,error_level,mean_dE00,p95_dE00,pareto,error\n";
    for (std::size_t r = 0; r < settings.size(); ++r) {
        const CommonOptions& o = settings[r].options;
        const RowResult& row = rows[r];
        std::string message = row.error;
        std::replace(message.begin(), message.end(), ',', ';');
        std::replace(message.begin(), message.end(), '\n', ' ');
        csv += concat(stem, ",", settings[r].axis, ",", settings[r].label, ",", o.method, ",",
                      o.quadratureLevel, ",", o.raysPerPair, ",", o.backend, ",", patchCounts[r],
                      ",", o.wavelengths, ",", sampleCounts[r], ",", formatNumber(o.tolerance), ",",
                      csvNumber(row.meshSeconds), ",", csvNumber(row.formFactorSeconds), ",",
                      csvNumber(row.solveSeconds), ",", csvNumber(row.renderSeconds), ",",
                      csvNumber(row.totalSeconds), ",", row.peakBytes, ",", row.nonzeros, ",",
                      row.iterations, ",", csvNumber(row.residual), ",", row.converged ? 1 : 0, ",",
                      csvNumber(row.relativeRmsB), ",", csvNumber(row.relativeRmsY), ",",
                      row.errorLevel, ",", csvNumber(row.meanDeltaE), ",", csvNumber(row.p95DeltaE),
                      ",", row.pareto ? 1 : 0, ",", message, "\n");
    }
    auto written = writeFileAtomically(csvPath, [&](std::FILE* f) -> std::string {
        std::fputs(csv.c_str(), f);
        return "";
    });
    const std::string plotPath = withExtension(csvPath, ".png");
    const Rgb8Image plot = drawLogLogChart(chart);
    if (written) written = writePng(plotPath, plot.width, plot.height, plot.pixels);
    const std::string referencePath = withExtension(csvPath, "-reference.png");
    if (written) {
        const Image rgb = xyzToLinearSrgb(sweep.reference().xyz, sweep.exposureScale());
        written = writePng(referencePath, rgb.width, rgb.height, toSrgb8(rgb));
    }
    if (!written) {
        logError(written.error().message);
        return 1;
    }
    logInfo(concat("bench: wrote ", csvPath, ", ", plotPath, " and ", referencePath));
    if (cheapest >= 0) {
        logInfo(concat("bench: cheapest setting under the just-noticeable difference: ",
                       settings[cheapest].axis, " ", settings[cheapest].label, " (",
                       formatNumber(rows[cheapest].totalSeconds, 3), " s, mean dE00 ",
                       formatNumber(rows[cheapest].meanDeltaE, 3), ")"));
    } else {
        logInfo("bench: no setting is under the just-noticeable difference");
    }
    for (const RowResult& row : rows)
        if (!row.error.empty()) return 1;
    return 0;
}

}  // namespace daisy::app
