#pragma once
// The stages `daisy` subcommands share: scene -> patches (under --max-memory) -> the view-factor
// matrix on the chosen backend -> the spectral radiosity solve (DESIGN.md section 1). Errors are
// bad input or settings (exit status 2); their messages name the scene or the option.
#include <functional>
#include <memory>
#include <string>

#include "app/options.h"
#include "backend/backend.h"
#include "core/expected.h"
#include "geometry/auto_patch_size.h"
#include "geometry/patch_mesh.h"
#include "radiosity/form_factors.h"
#include "radiosity/radiosity_system.h"
#include "radiosity/solver.h"
#include "scene/scene.h"
#include "spectral/wavelength_set.h"

namespace daisy::app {

// FormFactorSettings from the common options (method, quadrature, rays, seed, threads, memory).
FormFactorSettings formFactorSettingsFrom(const CommonOptions& options);

// Loads the scene and logs its warnings.
Expected<Scene> loadSceneLogged(const CommonOptions& options);

// Builds the patches subdivided to maxEdge (0 = the input triangles), refusing more than
// --max-memory allows.
Expected<PatchMesh> buildPatchesWithin(const CommonOptions& options, const Scene& scene,
                                       double maxEdge);

// The scene and its patches at --subdivide (the input triangles when it is not given): what
// `info`, `formfactors` and `validate` start from.
struct ScenePatches {
    Scene scene;
    PatchMesh patches;
};
Expected<ScenePatches> loadScenePatches(const CommonOptions& options);

struct FormFactorRun {
    FormFactorResult result;
    std::string backendName;
};
// Prints the matrix memory estimate, refuses it over --max-memory, and builds F on --backend.
Expected<FormFactorRun> buildFormFactorsFor(const CommonOptions& options, const PatchMesh& patches);

// What --subdivide means when it is not given: `solve`, `formfactors` and `info` keep the input
// triangles; `render` and `view` choose a size (geometry/auto_patch_size.h).
enum class DefaultPatchSize { InputTriangles, Automatic };

// Everything a solve produces, with the wall time of each stage (seconds).
struct SolvedScene {
    Scene scene;
    SceneSpectralFacts facts;
    WavelengthSet wavelengths;
    double maxEdge = 0;  // the --subdivide used (0 = input triangles)
    bool automaticPatchSize = false;  // maxEdge chosen by chooseAutoPatchSize
    PatchMesh patches;
    RadiositySystem system;
    std::size_t fluorescentOperators = 0;  // operators with off-diagonal entries
    FormFactorRun formFactors;
    SolverResult solution;  // B: patchCount x m, W m^-2 nm^-1 per unit emission scale
    double loadSeconds = 0, meshSeconds = 0, viewFactorSeconds = 0, solveSeconds = 0;
};

// Load -> wavelength set (`auto`: UV samples only for UV lights with fluorescent materials) ->
// patches -> E and M -> F -> solve, logging the "view factors: ..." and "solve: ..." lines (and
// with --verbose the wavelength set and materials). A solve that stops at --max-iterations is a
// warning, not an error. `afterLoad`, when given, runs on the loaded scene before any other
// work, so a bad setting that depends on the scene (a --camera it lacks) fails fast.
Expected<SolvedScene> solveScene(const CommonOptions& options, DefaultPatchSize defaultSize,
                                 const std::function<Expected<void>(const Scene&)>& afterLoad = {});

}  // namespace daisy::app
