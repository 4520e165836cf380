#pragma once
// `daisy bench SCENE --reference path`: run time against image error, measured against the
// independent path tracer (pathtrace/path_tracer.h) instead of a finer daisy.
//
// - The reference: the path tracer at referenceSpp samples per pixel on the session's
//   wavelength set, in chunks of up to 1,024 spp with their own seeds (1000, 1001, ...), summed;
//   the sums, the per-pixel variance and the time are cached on disk after every chunk (keyed
//   by the scene file's bytes and the settings), so an interrupted reference resumes and a
//   larger referenceSpp extends the cached one. referenceNoisePercent stops it early once its
//   relative RMS noise is under that level.
// - The path tracer's error-time curve: fresh runs (seed 7, independent of the reference) at
//   1, 4, 16, 64 and 256 spp.
// - The radiosity rows: the automatic patch size (or the given one; labelled "auto") and two
//   finer ones (edge / 1.5, / 2), each with gather none at 1 spp, gather direct at 1 and 4 spp
//   without edge supersampling, gather direct at 1 spp with 16 and 64 samples at edges
//   (image/edge_sampling.h), and gather near at 1 spp with 16 at edges (`daisy render`'s
//   default); a row's time is the whole pipeline (patches, F without the cache, solve, image).
// Error (bench/image_error.h): relative RMS luminance with the reference's own noise taken out,
// and mean CIE76 / CIEDE2000 as displayed at the reference's exposure, emitter pixels and a
// 2-pixel neighbourhood left out. Output: the CSV, a log-log chart of both curves, the reference
// image and the error images of the automatic size's smooth, gathered and default images.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bench/image_error.h"
#include "core/expected.h"
#include "pipeline/session.h"

namespace daisy {

inline constexpr double kPathBenchTargetError = 0.02;  // relative RMS luminance, 2%

struct PathBenchOptions {
    // The radiosity rows' settings (subdivideMaxEdge unset: the automatic patch size); the
    // disk cache of F is never used: every row times its own build. The scene, the wavelength
    // set, the thread count and the gather's seed (formFactors.seed) serve the path tracer too.
    SessionSettings session;
    bool quick = false;  // 48 x 48 pixels, a reference of at most 64 spp, fewer rows (ctest)
    int referenceSpp = 4096;  // at most, rounded up to whole chunks
    double referenceNoisePercent = 0;  // > 0: stop the reference once its noise is under it
};

// The files. csv: `outputPath`, or bench-path-STEM.csv in the working folder; beside it, named
// by its stem: CSVSTEM.png (chart), CSVSTEM.reference.png, CSVSTEM.error-*.png; the reference
// cache CSVSTEM.path-reference.bin beside it, or STEM.path-reference.bin in `cacheDir` when
// that is not empty. STEM is the scene file's name without its extension.
struct PathBenchFiles {
    std::string csv, chart, referenceImage, referenceCache;
    std::string errorImage(const std::string& which) const;  // CSVSTEM.error-WHICH.png
};
PathBenchFiles pathBenchFiles(const std::string& scenePath, const std::string& outputPath,
                              const std::string& cacheDir);

struct PathBenchRow {
    // "path" | "radiosity" | "refused" (F over --max-memory: label says so, no run, no error)
    std::string kind;
    std::string label;
    double seconds = 0;
    uint64_t patches = 0;  // 0 for the path tracer
    ImageError error;
};

// The reference as used: samples per pixel, the path tracer's time over all chunks, and its
// relative RMS noise (a fraction) over the kept pixels.
struct PathReferenceSummary {
    int spp = 0;
    double seconds = 0;
    double noise = 0;
};

class PathBench {
public:
    // Opens the session (the scene, patches, E and M) and chooses the camera (square image).
    static Expected<PathBench> open(const PathBenchOptions& options);
    PathBench(PathBench&&) noexcept;
    PathBench& operator=(PathBench&&) noexcept;
    ~PathBench();

    // The finer rows' patch size and the emitter mask of the error; the error names the scene.
    Expected<void> prepare();
    // Reads the reference's chunks from `cachePath`, traces the missing ones (progress logged,
    // the cache written after each chunk); the error names the scene.
    Expected<PathReferenceSummary> reference(const std::string& cachePath);
    // The path tracer's curve, then the radiosity rows (writing their error images, failures to
    // write logged as warnings), each passed to `onRow` as it is measured and appended to `rows`.
    // A patch size whose all-pairs F is over --max-memory gives one "refused" row and ends
    // the radiosity rows (the finer sizes need more).
    Expected<void> runPathRows(std::vector<PathBenchRow>& rows,
                               const std::function<void(const PathBenchRow&)>& onRow);
    Expected<void> runRadiosityRows(const PathBenchFiles& files, std::vector<PathBenchRow>& rows,
                                    const std::function<void(const PathBenchRow&)>& onRow);
    // The CSV (error: it was not written), then the reference image and the chart (failures
    // logged as warnings).
    Expected<void> writeFiles(const PathBenchFiles& files,
                              const std::vector<PathBenchRow>& rows) const;

private:
    struct State;
    explicit PathBench(std::unique_ptr<State> state);
    std::unique_ptr<State> state_;
};

// Time the path tracer needs for `target` relative RMS error (denoised): log-log interpolation
// between the first "path" row under it and the one before; past the curve's end, extrapolated
// from its last row by the Monte Carlo law error ~ 1 / sqrt(time) (`extrapolated` set). NAN
// without path rows.
double pathTimeTo(const std::vector<PathBenchRow>& rows, double target, bool& extrapolated);

}  // namespace daisy
