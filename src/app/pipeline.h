#pragma once
// The stages `daisy` subcommands share: scene -> patches (under --max-memory) -> the view-factor
// matrix on the chosen backend (DESIGN.md section 1). Errors are bad input or settings (exit
// status 2); their messages name the scene or the option.
#include <memory>
#include <string>

#include "app/options.h"
#include "backend/backend.h"
#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "radiosity/form_factors.h"
#include "scene/scene.h"

namespace daisy::app {

// FormFactorSettings from the common options (method, quadrature, rays, seed, threads, memory).
FormFactorSettings formFactorSettingsFrom(const CommonOptions& options);

// Loads the scene and logs its warnings.
Expected<Scene> loadSceneLogged(const CommonOptions& options);

// Builds the patches subdivided to maxEdge (0 = the input triangles), refusing more than
// --max-memory allows.
Expected<PatchMesh> buildPatchesWithin(const CommonOptions& options, const Scene& scene,
                                       double maxEdge);

struct FormFactorRun {
    FormFactorResult result;
    std::string backendName;
};
// Prints the matrix memory estimate, refuses it over --max-memory, and builds F on --backend.
Expected<FormFactorRun> buildFormFactorsFor(const CommonOptions& options, const PatchMesh& patches);

}  // namespace daisy::app
