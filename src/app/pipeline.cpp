#include "app/pipeline.h"

#include "core/log.h"
#include "core/progress.h"
#include "core/strings.h"
#include "core/timer.h"
#include "radiosity/matrix_estimate.h"

namespace daisy::app {

FormFactorSettings formFactorSettingsFrom(const CommonOptions& options) {
    FormFactorSettings settings;
    parseFormFactorMethod(options.method, settings.method);  // CLI11 checked the name
    settings.quadratureLevel = options.quadratureLevel;
    settings.raysPerPair = options.raysPerPair;
    settings.stochasticRays = options.stochasticRays;
    settings.seed = options.seed;
    settings.threads = options.threads;
    settings.maxMemoryBytes = options.maxMemoryBytes;
    return settings;
}

Expected<Scene> loadSceneLogged(const CommonOptions& options) {
    auto scene = loadScene(options.scenePath, options.sceneLoadOptions());
    if (!scene) return scene.error();
    for (const std::string& warning : scene->warnings)
        logWarning(warning);
    return scene;
}

Expected<PatchMesh> buildPatchesWithin(const CommonOptions& options, const Scene& scene,
                                       double maxEdge) {
    const uint64_t patchLimit = options.maxMemoryBytes / kPatchMeshBytesPerPatch;
    auto patches = buildPatchMesh(scene.mesh, maxEdge, patchLimit);
    if (!patches) {
        return Error{concat(options.scenePath, ": ", patches.error().message, " (--max-memory ",
                            formatBytes(static_cast<double>(options.maxMemoryBytes)), ")")};
    }
    return patches;
}

Expected<ScenePatches> loadScenePatches(const CommonOptions& options) {
    auto scene = loadSceneLogged(options);
    if (!scene) return scene.error();
    auto patches = buildPatchesWithin(options, *scene, options.subdivideMaxEdge.value_or(0));
    if (!patches) return patches.error();
    return ScenePatches{std::move(*scene), std::move(*patches)};
}

Expected<FormFactorRun> buildFormFactorsFor(const CommonOptions& options,
                                            const PatchMesh& patches) {
    const MatrixEstimate estimate = estimateMatrixMemory(patches);
    logInfo(concat("view factors: ", formatCount(patches.patchCount()), " patches, ~",
                   formatCount(estimate.nonzeros), " non-zeros, ~",
                   formatBytes(static_cast<double>(estimate.matrixBytes)), " as CSR (estimate)"));
    if (estimate.matrixBytes > options.maxMemoryBytes) {
        return Error{concat(options.scenePath, ": the view-factor matrix needs about ",
                            formatBytes(static_cast<double>(estimate.matrixBytes)), " for ",
                            formatCount(patches.patchCount()), " patches, more than --max-memory ",
                            formatBytes(static_cast<double>(options.maxMemoryBytes)),
                            "; use a larger --subdivide or raise --max-memory")};
    }
    auto backend = makeBackend(options.backend, BackendOptions{options.device});
    if (!backend)
        return Error{concat("--backend ", options.backend, ": ", backend.error().message)};
    auto result = (*backend)->buildFormFactors(patches, formFactorSettingsFrom(options));
    if (!result) return withContext(result.error(), options.scenePath);
    return FormFactorRun{std::move(*result), (*backend)->name()};
}

namespace {}  // namespace

Expected<SolvedScene> solveScene(const CommonOptions& options, DefaultPatchSize defaultSize,
                                 const std::function<Expected<void>(const Scene&)>& afterLoad) {
    SolvedScene out;
    auto start = Clock::now();
    auto scene = loadSceneLogged(options);
    if (!scene) return scene.error();
    out.scene = std::move(*scene);
    if (afterLoad) {
        if (auto checked = afterLoad(out.scene); !checked) return checked.error();
    }
    auto facts = sceneSpectralFacts(out.scene);
    if (!facts) return facts.error();
    out.facts = *facts;
    auto set =
        makeWavelengthSet(options.wavelengthSpec, facts->hasUvLights, facts->hasFluorescence);
    if (!set)
        return Error{concat("--wavelengths ", options.wavelengths, ": ", set.error().message)};
    out.wavelengths = std::move(*set);
    out.loadSeconds = secondsSince(start);

    start = Clock::now();
    if (options.subdivideMaxEdge) {
        out.maxEdge = *options.subdivideMaxEdge;
    } else if (defaultSize == DefaultPatchSize::Automatic) {
        const AutoPatchSize size = chooseAutoPatchSize(out.scene.mesh);
        out.maxEdge = size.maxEdge;
        out.automaticPatchSize = true;
        logVerbose(concat("patches: automatic size --subdivide ", out.maxEdge, " (budget ",
                          formatCount(size.budget), " patches for ",
                          formatCount(out.scene.mesh.triangleCount()), " triangles)"));
    }
    auto patches = buildPatchesWithin(options, out.scene, out.maxEdge);
    if (!patches) return patches.error();
    out.patches = std::move(*patches);
    auto system = buildRadiositySystem(out.scene, out.patches, out.wavelengths);
    if (!system) return system.error();
    out.system = std::move(*system);
    for (const MaterialOperator& op : out.system.operators)
        out.fluorescentOperators += !op.isDiagonal;
    out.meshSeconds = secondsSince(start);

    start = Clock::now();
    auto formFactors = buildFormFactorsFor(options, out.patches);
    if (!formFactors) return formFactors.error();
    out.formFactors = std::move(*formFactors);
    out.viewFactorSeconds = secondsSince(start);
    const SparseMatrix& f = out.formFactors.result.matrix;
    logInfo(concat("view factors: ", formatCount(f.nonzeroCount()), " non-zeros in ",
                   formatDuration(out.formFactors.result.stats.totalSeconds), " on ",
                   out.formFactors.backendName));

    const WavelengthSet& w = out.wavelengths;
    logVerbose(concat("wavelengths: ", w.name(), ", ", w.size(), " samples ",
                      formatNumber(w.wavelengthNm(0)), "..",
                      formatNumber(w.wavelengthNm(w.size() - 1)), " nm",
                      facts->hasUvLights && facts->hasFluorescence
                          ? " (scene has UV lights and fluorescent materials)"
                          : ""));
    logVerbose(
        concat("materials: ", out.scene.materials.size(), " as ", out.system.operators.size(),
               " distinct re-radiation matrices, ", out.fluorescentOperators, " fluorescent",
               out.fluorescentOperators ? "" : " (wavelengths solved independently, M diagonal)"));

    start = Clock::now();
    SolverSettings settings;
    parseSolverKind(options.solver, settings.kind);  // CLI11 checked the name
    settings.tolerance = options.tolerance;
    settings.maxIterations = options.maxIterations;
    settings.threads = options.threads;
    auto solved = solveRadiosity(f, out.system, settings);
    if (!solved) return Error{concat(options.scenePath, ": ", solved.error().message)};
    out.solution = std::move(*solved);
    out.solveSeconds = secondsSince(start);
    if (!out.solution.converged) logWarning(concat(options.scenePath, ": ", out.solution.warning));
    logInfo(concat("solve: ", out.solution.iterations, " iterations, residual ",
                   formatNumber(out.solution.residual, 3), ", ",
                   formatNumber(out.solution.seconds, 3), " s (", options.solver, ", ",
                   formatCount(out.system.patchCount), " patches x ", out.system.wavelengthCount,
                   " wavelengths", out.fluorescentOperators ? ", fluorescence" : "", ")"));
    return out;
}

}  // namespace daisy::app
