// libFuzzer target: the whole pipeline on tiny scenes, through the library (not app/): the
// first byte picks the format (bit 0: .gltf / .obj) and the patch size (bit 1: subdivide to
// half the scene's size); scenes over 64 triangles or 256 patches are skipped. Load -> the
// session (patches, E and M on the daisyriot wavelengths, F on the cpu backend, solve, display
// colours) -> an 8 x 8 render.
// Any stage may refuse with an Error; none may crash, and a solved B must be finite.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "fuzz_files.h"
#include "geometry/patch_mesh.h"
#include "image/camera.h"
#include "image/renderer.h"
#include "pipeline/session.h"
#include "pipeline/vertex_radiance.h"
#include "scene/load_scene.h"
#include "scene/validate_scene.h"
#include "spectral/wavelength_set.h"
#include "spectral/wavelength_spec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    const std::string_view bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
    const std::string path = daisy::fuzz::writeScratch(data[0] & 1 ? "p.obj" : "p.gltf", bytes);
    daisy::SceneLoadOptions load;
    load.maxMemoryBytes = daisy::fuzz::kFuzzMaxMemoryBytes;
    auto scene = daisy::loadScene(path, load);
    if (!scene || scene->mesh.triangleCount() > 64) return 0;

    const double maxEdge = data[0] & 2 ? daisy::sceneExtent(scene->mesh).diagonal / 2 : 0.0;
    if (daisy::estimatePatchCount(scene->mesh, maxEdge) > 256) return 0;

    // The session, as every front end runs it: patches, E and M, F on the cpu backend, solve.
    daisy::SessionSettings settings;
    settings.scenePath = path;
    settings.backend = "cpu";
    settings.subdivideMaxEdge = maxEdge;
    settings.formFactors.threads = 1;
    settings.formFactors.progress = false;
    settings.wavelengths = *daisy::parseWavelengthSpec("daisyriot");
    settings.wavelengthsText = "daisyriot";
    settings.solver.maxIterations = 20;
    settings.solver.threads = 1;
    settings.maxMemoryBytes = uint64_t(64) << 20;
    settings.logStages = false;
    auto session = daisy::Session::fromScene(std::move(*scene), std::move(settings));
    if (!session) return 0;
    auto solved = session->solve();
    if (!solved) return 0;
    for (double b : solved->radiosity) {
        if (!std::isfinite(b)) std::abort();  // a solve that succeeds is finite
    }
    for (float value : session->cornerChannels(false)) {
        if (!std::isfinite(value)) std::abort();  // nor are its display colours
    }

    auto camera = daisy::chooseCamera(session->scene(), "", 1.0);
    if (!camera) return 0;
    camera->aspectRatio = 0;
    const daisy::PatchMesh& patches = session->patches();
    std::vector<float> patchValues(patches.patchCount(), 1.0f);
    const std::vector<float> corners = daisy::cornerValues(patches, patchValues, 1);
    daisy::RenderSettings render;
    render.width = 8;
    render.height = 8;
    render.threads = 1;
    const float background[1] = {0.0f};
    (void)daisy::renderCornerValues(patches, *camera, render, corners, 1, background);
    return 0;
}
