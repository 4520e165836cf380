#pragma once
// The options of the `daisy` command line (DESIGN.md section 9), parsed and range-checked by
// CLI11 before any work starts. Stages that land later read the same structs.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "hierarchical/hierarchical_links.h"
#include "radiosity/form_factors.h"
#include "radiosity/solver.h"
#include "scene/load_scene.h"
#include "spectral/wavelength_spec.h"

namespace daisy::app {

struct CommonOptions {
    std::string scenePath;
    std::string backend = "auto";  // "auto" or a name of pipeline/backend_registry.h
    std::string device;  // --device: GPU index or part of its name; empty = first suitable
    std::string vulkanRays = "auto";  // --vulkan-rays: auto | query | software
    // The form-factor settings' names and defaults are the library's (radiosity/form_factors.h).
    std::string method = formFactorMethodName(FormFactorSettings{}.method);
    std::string transport = "auto";  // --transport: auto | matrix | hierarchical
    double linkTolerance = HierarchySettings{}.linkTolerance;  // --link-tolerance
    int quadratureLevel = FormFactorSettings{}.quadratureLevel;  // L: 4^L points per patch
    int raysPerPair = FormFactorSettings{}.raysPerPair;  // K shadow rays per pair; 0 = none
    int stochasticRays = FormFactorSettings{}.stochasticRays;  // N rays per patch (stochastic)
    // --subdivide: scene units; 0 = keep the input triangles; unset = `render` and `view` choose
    // a patch size from the scene (geometry/auto_patch_size.h), other commands keep the triangles
    std::optional<double> subdivideMaxEdge;
    std::string wavelengths = "auto";  // see spectral/wavelength_spec.h
    WavelengthSpec wavelengthSpec;  // parsed from `wavelengths`
    std::string solver = solverKindName(SolverSettings{}.kind);
    double tolerance = SolverSettings{}.tolerance;  // relative residual
    int maxIterations = SolverSettings{}.maxIterations;
    int threads = 0;  // 0 = all hardware threads
    uint64_t seed = 1;
    std::string cacheDir;  // --cache DIR; empty = the default folder (unless noCache)
    bool noCache = false;  // --no-cache: neither read nor write the disk cache of F
    std::string cacheSizeText;  // --cache-size as typed; parsed into cacheSizeBytes
    uint64_t cacheSizeBytes = 0;  // the disk cache's size limit; 0 = the default
    std::string maxMemoryText;  // as typed; parsed into maxMemoryBytes
    uint64_t maxMemoryBytes = 0;  // default: 80% of physical memory
    bool quiet = false;
    bool verbose = false;
    std::string mtlConvention = "standard";  // standard | daisyriot
    std::string materialsPath;  // --materials FILE.json

    SceneLoadOptions sceneLoadOptions() const;
};

struct RenderOptions {
    std::string outputPath = "render.png";
    int width = 640;
    int height = 0;  // 0 = width / the camera's aspect ratio (4:3 when it has none)
    std::string camera;  // name or index; empty = first camera or automatic framing
    int samplesPerPixel = 1;
    // samples of the pixels on a silhouette, crease or material boundary (radiosity only:
    // image/edge_sampling.h); 0 = every pixel takes samplesPerPixel
    int edgeSamplesPerPixel = 16;
    std::string exposure = "auto";  // "auto" or a fixed EV
    bool spectralExr = false;  // .exr: one channel per wavelength sample (Fichet et al. 2021)
    std::string background = "0,0,0";  // R,G,B of missed rays, linear sRGB in [0, 1]
    // radiosity (the solve, then the ray-cast image) | path (the independent path tracer,
    // src/pathtrace/: no F, no solve)
    std::string integrator = "radiosity";
    // none (the smooth vertex-radiance image, as the viewer shows it) | direct (plus per-sample
    // direct light from the emitters: image/final_gather.h) | near (direct, plus the near-field
    // indirect light and the buried parts of patches: image/near_field.h)
    std::string gather = "near";
    int gatherRays = 64;  // shadow segments per penumbra pixel (image/final_gather.h)
    double nearRadius = 2;  // --gather near: R in patch sizes (image/near_field.h)
};

struct ViewOptions {
    std::string screenshotPath;
    std::string saveMaterialsPath;  // --save-materials: the edited materials as --materials JSON
    int frames = 0;  // 0 = run until the window closes
    std::string camera;  // name or index; empty = first camera or automatic framing
    int width = 1280;  // the window's size at start
    int height = 720;
    std::string exposure = "auto";  // "auto" or a fixed EV
    std::vector<std::string> edits;  // --edit NAME.FIELD=VALUE (viewer/material_edit.h)
    bool exerciseWindow = false;  // --exercise-window: resize and minimise (tests)
    bool panel = false;  // --panel: the panel in the --frames mode too
    std::string pick;  // --pick X,Y: framebuffer pixel to pick, as a click
    std::string display;  // --display colour|luminance|wavelength:NM,flat,wireframe
};

struct ExportOptions {
    std::string matrixPath;  // formfactors -o
    std::string patchesPath;  // --patches-out
};

struct ValidateOptions {
    std::string against = "reference";
    // An entry agrees when |a - b| <= relativeTolerance * max(|a|, |b|) + absoluteTolerance.
    double relativeTolerance = 1e-4;
    double absoluteTolerance = 1e-7;
    int worstShown = 10;  // worst entries listed
};

struct BenchOptions {
    bool stress = false;  // the numerical stress suite instead of the time/error sweep
    bool quick = false;  // reduced sizes (what ctest runs)
    std::string outputPath;  // CSV
    // path (the default): against the path-traced reference (bench/path_bench.h); daisy: the
    // settings sweep against a converged high-setting daisy solution (bench/sweep.h)
    std::string reference = "path";
    int referenceSpp = 4096;  // samples per pixel of the path-traced reference (at most)
    double referenceNoise = 0;  // percent: the reference stops once its noise is under it
};

// `daisy cache ACTION`: the disk cache's folder as a whole (app/cache.cpp).
struct CacheOptions {
    std::string action;  // list | clear | prune
    std::string cacheDir;  // --cache DIR; empty = the default folder
    std::string cacheSizeText;  // --cache-size as typed; empty = the default limit
};

// Adds the scene argument and the common options to a subcommand.
void addCommonOptions(CLI::App& command, CommonOptions& options, bool sceneRequired = true);

// Fills the fields parsed from already-validated text (wavelengthSpec, maxMemoryBytes,
// cacheSizeBytes).
void finishCommonOptions(CommonOptions& options);

// `--background R,G,B`: three comma-separated numbers in [0, 1]; nullopt for anything else.
std::optional<std::array<double, 3>> parseBackground(const std::string& text);

// Adds --cache-size BYTES (a size as --max-memory takes it) to a command, into `text`.
void addCacheSizeOption(CLI::App& command, std::string& text);

// Physical memory of this machine in bytes (0 when unknown).
uint64_t physicalMemoryBytes();

// A finite number in [lo, hi]: CLI11's Range and NonNegativeNumber let NaN through, since every
// comparison with it is false. The message names the value and the range.
CLI::Validator finiteNumber(double lo, double hi);
// A seed: a decimal integer from 0 to 2^64 - 1, without sign (CLI11 wraps -1 and 2^64 around).
extern const CLI::Validator kSeed;

}  // namespace daisy::app
