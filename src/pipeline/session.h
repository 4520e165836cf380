#pragma once
// The session (DESIGN.md section 1): one object that carries a scene through every stage, for
// every front end (the command line, the viewer, `daisy bench` and the stress suite):
//     scene -> wavelength set -> patches -> E and M -> F (a backend, or the disk cache) -> B
//     -> display colours.
// The transport (radiosity/transport.h: F, built by a backend or read from the disk cache) is
// built once and kept; a material or wavelength edit rebuilds only E and M, and the next solve
// starts warm from the last B. Front ends reach the transport only through this interface and
// radiosity/transport.h, never its representation, so that can change without touching them. Errors
// are bad input or settings (exit status 2 in the app) and name the scene or the option; the
// session logs its stage lines (core/log.h).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "backend/backend.h"
#include "core/cancel.h"
#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "hierarchical/hierarchical_links.h"
#include "pipeline/channel_layout.h"
#include "pipeline/formfactor_cache.h"
#include "pipeline/solution_cache.h"
#include "radiosity/energy.h"
#include "radiosity/form_factors.h"
#include "radiosity/matrix_estimate.h"
#include "radiosity/patch_exposure.h"
#include "radiosity/radiosity_system.h"
#include "radiosity/solver.h"
#include "radiosity/transport.h"
#include "scene/load_scene.h"
#include "scene/scene.h"
#include "spectral/color.h"
#include "spectral/wavelength_set.h"
#include "spectral/wavelength_spec.h"

namespace daisy {

// What the patch size is when subdivideMaxEdge is not given: `formfactors` and `validate` keep
// the input triangles; `render`, `view`, `solve` and `info` choose one
// (geometry/auto_patch_size.h), so `info` and `solve` describe the patches `render` solves.
enum class PatchSizeDefault { InputTriangles, Automatic };

// How light moves between patches (--transport): the all-pairs matrix F
// (radiosity/matrix_transport.h), or links between nodes of a cluster hierarchy
// (hierarchical/hierarchical_transport.h). Auto is decided when the session opens, from the
// patches (chooseTransport); settings().transport is Matrix or Hierarchical after that.
enum class TransportKind { Auto, Matrix, Hierarchical };
const char* transportKindName(TransportKind kind);

// From this estimated size of the matrix F on, `auto` takes the hierarchical transport. Below
// it the matrix path is at least as accurate and still affordable: the Cornell box at 15,132
// patches (F ~1.10 GiB) is 1.23% from the path tracer with the matrix and 1.73% with the links;
// above it the matrix path's time and memory grow as n^2 (the 30,000-triangle interior's F is
// 6.6 GiB) (docs/hierarchical.md, "Which transport").
inline constexpr uint64_t kAutoHierarchicalMatrixBytes = uint64_t(2) << 30;

// What `auto` picks for a matrix F estimated at `matrixBytes`: the hierarchy from
// kAutoHierarchicalMatrixBytes on or when F would not fit in maxMemoryBytes, but only where it
// can run (backend `auto` or `cpu`: only the cpu backend evaluates links); the matrix otherwise.
TransportKind chooseTransport(uint64_t matrixBytes, uint64_t maxMemoryBytes,
                              const std::string& backend);

struct SessionSettings {
    std::string scenePath;  // loaded by open(); named in messages
    SceneLoadOptions load;
    std::string backend = "auto";  // a name of pipeline/backend_registry.h
    std::string device;  // --device
    VulkanRays vulkanRays = VulkanRays::Auto;  // --vulkan-rays
    // A backend already made (makeBackend) to build F with instead of making one from `backend`:
    // sessions that share it share its device (a Vulkan device takes ~0.6 s to create on
    // lavapipe). `backend` must still name it (the cache key's family comes from the name).
    std::shared_ptr<Backend> backendInstance;
    FormFactorSettings formFactors;  // method, L, K, N, seed, threads; maxMemoryBytes below
    TransportKind transport = TransportKind::Matrix;
    HierarchySettings hierarchy;  // the hierarchical transport's oracle
    std::optional<double> subdivideMaxEdge;  // scene units; 0 = the input triangles
    PatchSizeDefault defaultPatchSize = PatchSizeDefault::InputTriangles;
    WavelengthSpec wavelengths;  // `auto` adds UV samples only where the scene needs them
    std::string wavelengthsText = "auto";  // as typed, for messages
    // An explicit wavelength set, used instead of `wavelengths` when given (bench's reference).
    std::optional<WavelengthSet> wavelengthSet;
    SolverSettings solver;  // kind, tolerance, maxIterations, threads
    std::optional<std::filesystem::path> cacheDirectory;  // the disk cache of F; unset = none
    uint64_t cacheSizeBytes = 0;  // its size limit; 0 = the default (core/cache_folder.h)
    uint64_t maxMemoryBytes = UINT64_MAX;  // refuse patches and F needing more
    bool logStages = true;  // log the stage lines ("view factors: ...", "solve: ...")
};

// The options a backend made for these settings gets: the device and the vulkan backend's rays.
BackendOptions backendOptionsOf(const SessionSettings& settings);

// Where F came from and what building it did.
struct FormFactorReport {
    std::string backendName;  // the backend that built F (the one that built the cached copy
                              // is not recorded: backendName is then "cache")
    bool fromCache = false;
    std::string cachePath;  // the entry read or written; empty without a cache
    std::string cacheWarning;  // a rejected entry, one line (already logged); a failed store
                               // is logged later (Session::finishCacheWrite)
    FormFactorStats stats;  // of the build (for a cached F: the stats stored with it)
    double seconds = 0;  // wall time of this call: the cache read, or the build (not the store)
};

struct SolveRequest {
    bool warmStart = true;  // start from the last solution when there is one (of the same size)
    const CancelToken* cancel = nullptr;
    ProgressObserver onProgress;  // of the F build, when the solve needs F first
    std::function<void(int iteration, std::span<const double> radiosity)> onIteration;
    std::optional<int> maxIterations;  // overrides the settings' (the viewer's bounce stepping)
    std::optional<SolverKind> kind;  // overrides the settings' solver
    // The disk cache of converged solutions (pipeline/solution_cache.h), both ignored without a
    // cache folder and when maxIterations or kind is given. useSolutionCache: look up a
    // converged solution for these settings first (then no solve), and store a converged result
    // in the background. storeSolution: only the store (the viewer's edits, whose re-solves are
    // what it shows and measures).
    bool useSolutionCache = false;
    bool storeSolution = false;
};

// A lookup of the disk cache's converged solutions (Session::loadCachedSolution).
struct SolutionCacheReport {
    bool hit = false;
    std::string path;  // the entry read; empty without a cache
    std::string warning;  // a rejected entry, one line (already logged)
    double seconds = 0;  // the key and the read
};

// Wall time of each stage, seconds (0 for a stage not run).
struct SessionTimings {
    double loadSeconds = 0;  // scene file, wavelength set
    double meshSeconds = 0;  // patches, E and M
    double viewFactorSeconds = 0;  // F: the cache read or the build
    double solveSeconds = 0;  // the last solve
};

class Session {
public:
    // Loads settings.scenePath (warnings logged), then chooses the wavelength set and builds the
    // patches, E and M; F is built on first need. `afterLoad`, when given, runs on the loaded
    // scene before any other work, so a setting that depends on the scene fails fast.
    static Expected<Session> open(
        SessionSettings settings,
        const std::function<Expected<void>(const Scene&)>& afterLoad = {});
    // The same from a scene in memory (the stress suite, tests, bench rows).
    static Expected<Session> fromScene(Scene scene, SessionSettings settings);

    Session(Session&&) noexcept;
    Session& operator=(Session&&) noexcept;
    ~Session();

    const SessionSettings& settings() const;
    const Scene& scene() const;
    const SceneSpectralFacts& facts() const;
    const WavelengthSet& wavelengths() const;
    const PatchMesh& patches() const;
    // Patch means of the materials whose colour varies (textures, vertex colours; empty when
    // none): what the solve used, and what the image's texture detail divides by.
    const PatchAppearance& appearance() const;
    double patchMaxEdge() const;  // the --subdivide used (0 = the input triangles)
    bool automaticPatchSize() const;  // patchMaxEdge chosen by chooseAutoPatchSize
    const RadiositySystem& system() const;
    std::size_t fluorescentOperatorCount() const;  // operators with off-diagonal entries
    const SessionTimings& timings() const;

    // ---- F ----
    MatrixEstimate matrixEstimate() const;
    // The cache key of F for these patches and settings (pipeline/formfactor_cache.h).
    FormFactorKey formFactorKey() const;
    // The disk cache's entry that buildFormFactors reads: F's, or with the hierarchical
    // transport the links' (pipeline/links_cache.h); empty without a cache folder.
    std::filesystem::path formFactorsCachePath() const;
    // True when the disk cache holds that entry (F: a header check; links: the file exists).
    bool formFactorsCached() const;
    // Makes F available: from memory (no work), the disk cache, or the backend (then stored in
    // the cache by a background task, so the solve need not wait for the write: a failed store
    // is logged as a warning by finishCacheWrite, not in the report). Refuses a matrix over
    // maxMemoryBytes before building. A cancelled build is an error saying so, and leaves no F.
    // `onProgress`, when given, is told of the build's progress (core/progress.h).
    Expected<FormFactorReport> buildFormFactors(const CancelToken* cancel = nullptr,
                                                const ProgressObserver& onProgress = {});
    // Builds F on the backend, bypassing the cache in both directions (validate, bench).
    Expected<FormFactorReport> buildFormFactorsUncached(const std::string& backend,
                                                        const CancelToken* cancel = nullptr,
                                                        const ProgressObserver& onProgress = {});
    // Waits for the background stores of F and B started by buildFormFactors and solve (no work
    // when none is pending) and returns their warnings ("F not cached: ...", one per line), which
    // it also logs; "" on success. Called by formFactorsCached and the destructor.
    std::string finishCacheWrite() const;
    bool hasFormFactors() const;
    // The transport built by buildFormFactors (precondition: hasFormFactors()); the shared
    // handle keeps it alive past a rebuild (validate compares two builds).
    const Transport& transport() const;
    std::shared_ptr<const Transport> sharedTransport() const;
    uint64_t formFactorBuildCount() const;  // times a backend built F for this session
    // What to change when F (or the patches) would exceed --max-memory: a larger --subdivide
    // when the patches are subdivided, else that the input triangles cannot be merged.
    std::string memoryAdvice() const;
    // Uses `matrix` as F (a matrix computed elsewhere: tests, the stress suite's own drivers).
    void setFormFactors(SparseMatrix matrix);
    // The hierarchical transport on `backend` (only cpu evaluates links so far); with
    // `useCache` (buildFormFactors: not the uncached build) read from and stored in the disk
    // cache's links entries (pipeline/links_cache.h). `onProgress` is told of the stages
    // "links" (the refinement) and "near factors".
    Expected<FormFactorReport> buildHierarchical(const std::string& backend,
                                                 const CancelToken* cancel, bool useCache,
                                                 const ProgressObserver& onProgress = {});
    // With the hierarchical transport: true when an edit since its links were refined moved
    // light where they may be too coarse for the oracle (importanceGrew, hierarchical/
    // link_oracle.h, with kRelinkFactor), such as a new emitter or a dark cavity made bright.
    bool linksOutdated() const;
    static constexpr double kRelinkFactor = 1.4;  // every link within 2 epsilon until then
    // Refines the links again for the materials and lights in hand (the disk cache's entry for
    // them, or a build) and replaces the transport; the solution stays as the warm start. The
    // old links are kept until the new ones are ready, so both count against --max-memory. A
    // cancelled or refused refinement keeps the old links.
    Expected<FormFactorReport> refineLinks(const CancelToken* cancel = nullptr,
                                           const ProgressObserver& onProgress = {});

    // ---- edits (F untouched) ----
    // Replaces material `index` and rebuilds E and M; the solution is kept as the warm start.
    // When the edit adds or removes the scene's UV lights or fluorescence, the wavelength set is
    // made again from the settings' spec (`auto` gains or loses its UV samples) and a solution of
    // the old size is dropped. Errors name the material and leave the session as it was.
    Expected<void> setMaterial(std::size_t index, Material material);
    // Replaces punctual light `index` (KHR_lights_punctual) and rebuilds E; its shadow rays are
    // traced again only when it moved or its cone or range changed. Same rules as setMaterial.
    Expected<void> setLight(std::size_t index, PunctualLight light);
    // Chooses a new wavelength set (E, M rebuilt; the solution is dropped: its size changes).
    Expected<void> setWavelengths(const WavelengthSpec& spec, const std::string& text);

    // ---- solve ----
    // Solves B = E + M F B (building F first if needed) for the patches' exposed parts
    // (radiosity/exposed_system.h: a patch partly buried under an object reflects all it gathers
    // from its exposed part), and returns the whole-patch means B = E + phi (B' - E); `gathered`
    // is F B'. Not converging within the iteration limit is a warning (logged, except when
    // request.maxIterations bounds the solve), not an error; cancellation returns the last
    // iterate with cancelled = true. With request.useSolutionCache, the converged solution the
    // disk cache holds for these settings is adopted instead (no iterations, changeHistory
    // empty); with it or request.storeSolution a converged result is stored there in the
    // background.
    Expected<SolverResult> solve(const SolveRequest& request = {});
    // The exposed share of every patch (radiosity/patch_exposure.h), probed on first use (rays).
    Expected<const PatchExposure*> exposure() const;
    // The energy bookkeeping of the solution (radiosity/energy.h), of the exposed parts when the
    // last solve used them (then light reaching a buried part is not counted as escaped).
    // Precondition: hasSolution() from solve().
    EnergyBalance energyBalance() const;
    bool hasSolution() const;
    const SolverResult& solution() const;  // precondition: hasSolution()
    // The key of the disk cache's converged solution for the current F key, system (materials,
    // wavelengths) and solver settings (pipeline/solution_cache.h).
    SolutionKey solutionKey() const;
    // Adopts the converged B and G the disk cache holds under solutionKey(), when it holds them:
    // the solution of a solve with the settings' solver, without F or a solve (the viewer's warm
    // open). A miss or a rejected entry (logged) changes nothing.
    SolutionCacheReport loadCachedSolution();
    // Sets B = E (the viewer's "reset to emission"; the next warm start starts there).
    void resetToEmission();
    // Uses `radiosity` (n x m) as the solution (the bench's analytic furnace answer; with
    // `converged` false, a picture to show and start the next solve from, not an answer).
    void setSolution(std::vector<double> radiosity, bool converged = true);

    // ---- the first bounce of an edit ----
    // Replaces the solution's radiosity of the patches with selected[i] != 0 by one bounce of
    // the light that reached them in the last finished solve, B = E + M G with the current
    // materials, on the same exposed parts as the solve (radiosity/exposed_system.h): the
    // viewer's preview of an edit, exact for a converged solve whose materials did not change.
    // False (nothing changed) when no finished solve of this wavelength set left its G.
    bool previewBounce(std::span<const uint8_t> selected);
    // Probes the patches' exposed parts and derives their system for the transport in hand (a
    // solve's first step), so that previewBounce after a solution adopted from the cache
    // (loadCachedSolution) is immediate. Precondition: hasFormFactors().
    Expected<void> prepareExposedParts();

    // ---- display colours (of the solution; B = E when there is none) ----
    // The radiosity shown: the solution's B, or E before any solve (n x m).
    const std::vector<double>& displayRadiosity() const;
    // G of the last finished solve (n x m; empty when none), the irradiance of the exposed
    // parts the solve used.
    const std::vector<double>& lastGathered() const;
    ChannelLayout channelLayout(bool spectral) const;
    // Per patch, the channels of channelLayout(spectral) (channel_layout.h), row-major.
    std::vector<float> patchChannels(bool spectral) const;
    // Radiance XYZ per patch.
    std::vector<Xyz> patchRadianceXyz() const;
    // The same smoothed per patch corner (pipeline/vertex_radiance.h): patchCount x 3 corners x
    // channels, for rasterising and ray-cast images.
    std::vector<float> cornerChannels(bool spectral) const;
    // Linear sRGB radiance per patch corner (patchCount x 3 x 3), times `scale`.
    std::vector<float> cornerLinearSrgb(double scale = 1) const;

    struct State;  // opaque: defined in session.cpp

private:
    explicit Session(std::unique_ptr<State> state);
    // E and M (and the wavelength set, when an edit adds or removes UV lights or fluorescence)
    // from the scene as it is now; an error leaves them as they were.
    Expected<void> rebuildSystem();
    std::unique_ptr<State> state_;
};

}  // namespace daisy
