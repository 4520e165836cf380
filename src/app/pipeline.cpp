#include "app/pipeline.h"

#include "core/log.h"
#include "core/strings.h"
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

}  // namespace daisy::app
