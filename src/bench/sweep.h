#pragma once
// `daisy bench SCENE --reference daisy`: run time against error. Sweeps the settings that trade
// time for accuracy one at a time around the default row's settings (the command line's, i.e. the
// defaults unless overridden): method, quadrature L, rays K, subdivision (patch budgets),
// wavelength set, solver tolerance and backend. Every row runs the whole pipeline from the
// scene's triangles (patches, F, radiosity system and solve, shading and a ray-cast image),
// timing each stage and taking the peak resident memory of the row (core/memory.h), and measures
// its error against the reference:
// - the analytic answer when the scene is a furnace (furnaceSolution), else
// - a converged high-setting solution of the same scene (hybrid L=2, K=64, the fine wavelength
//   set with UV excitation samples, tolerance 1e-6, twice the default row's patches), computed
//   once and cached on disk (keyed by the scene file's bytes and those settings).
// Errors: area-weighted relative RMS of B over patches and wavelength samples (the reference
// spectrum interpolated to the row's samples) and of the luminance Y; patch by patch when the
// row's patches are the reference's, else per source triangle (area-weighted means); and the
// image's mean and 95th-percentile CIEDE2000 against the reference render (same camera and
// exposure, 8-bit sRGB as displayed). Output: a CSV, a log-log plot of image error against
// time with the Pareto front and the just-noticeable difference marked, and the reference image.
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bench/chart.h"
#include "core/expected.h"
#include "pipeline/session.h"

namespace daisy {

// Image error a person just notices: mean CIEDE2000 of 1 (Sharma et al. 2005 state Delta E00
// ~ 1 as the threshold of a just-perceptible difference for side-by-side patches).
inline constexpr double kJustNoticeableDeltaE = 1.0;

// The reference: the accurate method at high settings, converged far below the JND.
inline constexpr int kSweepReferenceLevel = 2;
inline constexpr int kSweepReferenceRays = 64;
inline constexpr double kSweepReferenceTolerance = 1e-6;
inline constexpr int kSweepReferenceMaxIterations = 100000;

struct SweepOptions {
    // The default row: the scene file and how it is loaded, backend and device, F's method, L, K,
    // N, seed and threads, subdivideMaxEdge (unset: the automatic patch size), wavelengths and
    // solver. The disk cache of F is never used: every row times its own build.
    SessionSettings session;
    bool quick = false;  // reduced sizes and one row per axis (what ctest runs)
};

// The files of a sweep. csv: `outputPath`, or bench-STEM.csv in the working folder; chart and
// referenceImage beside it as CSVSTEM.png and CSVSTEM-reference.png; referenceCache beside it as
// CSVSTEM.reference.bin, or in `cacheDir` (when not empty) as STEM.bench-reference.bin. STEM is
// the scene file's name without its extension.
struct SweepFiles {
    std::string csv, chart, referenceImage, referenceCache;
};
SweepFiles sweepFiles(const std::string& scenePath, const std::string& outputPath,
                      const std::string& cacheDir);

// One row to run: the default row's settings with one change.
struct SweepSetting {
    std::string axis;  // "default", "method", "quadrature", ...
    std::string label;  // what differs from the default, e.g. "K=64"
    SessionSettings session;
    std::optional<double> maxEdge;  // the patch size, when not the default row's
};

// What one row measured. Times in seconds; NAN where not measured.
struct SweepRow {
    std::string axis, label;  // of its SweepSetting
    std::string method;  // the settings, as the CSV names them
    int quadratureLevel = 0, raysPerPair = 0;
    std::string backend, wavelengths;
    double tolerance = 0;
    std::string error;  // non-empty: the row failed with this message
    double meshSeconds = 0, formFactorSeconds = 0, solveSeconds = 0, renderSeconds = 0;
    double totalSeconds = 0;
    uint64_t peakBytes = 0;
    uint64_t nonzeros = 0;
    uint64_t patches = 0;  // 0 when the row failed
    std::size_t samples = 0;  // wavelength samples; 0 when the row failed
    int iterations = 0;
    double residual = 0;
    bool converged = false;
    double relativeRmsB = NAN, relativeRmsY = NAN;
    std::string errorLevel;  // "patch" or "triangle"
    double meanDeltaE = NAN, p95DeltaE = NAN;
    bool pareto = false;  // on the front of (totalSeconds, meanDeltaE): markParetoFront
};

// How the reference was obtained.
struct SweepReference {
    bool analytic = false;  // the furnace's closed form
    bool fromCache = false;
    uint64_t patches = 0;
    std::size_t samples = 0;  // wavelength samples
    double seconds = 0;  // the time its computation took (when it was computed)
};

class SettingsSweep {
public:
    // Loads the scene (warnings logged), chooses the camera, the default row's patch size and the
    // reference's. Errors: the scene file, its meshing.
    static Expected<SettingsSweep> open(const SweepOptions& options);
    SettingsSweep(SettingsSweep&&) noexcept;
    SettingsSweep& operator=(SettingsSweep&&) noexcept;
    ~SettingsSweep();

    // The reference, read from `cachePath` when its key matches, else computed (progress
    // logged) and written there. Errors: the pipeline's, a reference solve that did not
    // converge, the cache file not written.
    Expected<SweepReference> reference(const std::string& cachePath);
    // The rows, the default first; after reference().
    std::vector<SweepSetting> settings() const;
    // Runs one row and measures it against the reference; a failure is the row's `error`.
    SweepRow run(const SweepSetting& setting);
    // files.csv (sweepCsv), files.chart (sweepChart) and files.referenceImage.
    Expected<void> writeFiles(const SweepFiles& files, const std::vector<SweepRow>& rows) const;

private:
    struct State;
    explicit SettingsSweep(std::unique_ptr<State> state);
    std::unique_ptr<State> state_;
};

// Marks the rows on the Pareto front of (total time, mean CIEDE2000), failed rows left out, and
// returns the cheapest of them under kJustNoticeableDeltaE (-1 when none is).
int markParetoFront(std::vector<SweepRow>& rows);

// The CSV (a header line, one line per row; commas in an error message become semicolons) and
// the log-log chart of mean CIEDE2000 against time, one series per axis. `stem` names the scene.
std::string sweepCsv(const std::string& stem, const std::vector<SweepRow>& rows);
ChartSpec sweepChart(const std::string& stem, const std::vector<SweepRow>& rows);

// The furnace oracle: a closed mesh (every edge shared by exactly two patches), one diagonal
// (non-fluorescent) material operator and the same emission on every patch give G = B, so
// B = E + rho B, i.e. B = E / (1 - rho) per wavelength, exactly. nullopt for any other system.
std::optional<std::vector<double>> furnaceSolution(const PatchMesh& patches,
                                                   const RadiositySystem& system);

}  // namespace daisy
