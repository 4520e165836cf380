// The analytic fixtures of tools/make_analytic_scenes.py against their closed forms: the view
// factor between the two plates of parallel_plates.gltf and perpendicular_plates.gltf (the
// white furnace is checked through `daisy render` in tests/app/render_cli_test.cpp).
#include <gtest/gtest.h>

#include <string>

#include "geometry/patch_mesh.h"
#include "pipeline/backend_registry.h"
#include "radiosity/form_factors.h"
#include "scene/load_scene.h"
#include "test_util.h"
#include "verify/closed_forms.h"

namespace daisy {
namespace {

// F from the source plate (material 0) to the target plate (material 1): sum over patch pairs
// of A_i F_ij, divided by the source's area (reciprocity, DESIGN.md section 2).
double plateFactor(const std::string& scenePath) {
    auto scene = loadScene(scenePath);
    EXPECT_TRUE(scene) << scene.error().message;
    if (!scene) return -1;
    auto patches = buildPatchMesh(scene->mesh, 0.125);
    EXPECT_TRUE(patches);
    auto backend = makeBackend("cpu", BackendOptions{});
    EXPECT_TRUE(backend) << backend.error().message;
    auto result = (*backend)->buildFormFactors(*patches, FormFactorSettings{});
    EXPECT_TRUE(result) << result.error().message;
    if (!result) return -1;
    const SparseMatrix& f = result->matrix;
    double sum = 0, sourceArea = 0;
    for (uint32_t i = 0; i < f.size; ++i) {
        if (patches->materials[i] != 0) continue;
        sourceArea += patches->areas[i];
        const auto columns = f.rowColumns(i);
        const auto values = f.rowValues(i);
        for (std::size_t k = 0; k < columns.size(); ++k) {
            if (patches->materials[columns[k]] == 1) sum += patches->areas[i] * values[k];
        }
    }
    return sum / sourceArea;
}

// Howell, "A Catalog of Radiation Heat Transfer Configuration Factors", C-11 (directly opposed
// rectangles, X = Y = 1): 0.19982. 1% allows for the 128 patches per plate.
TEST(AnalyticScenes, ParallelPlates) {
    EXPECT_NEAR(plateFactor(test::assetPath("scenes/parallel_plates.gltf")), verify::kHowellC11,
                0.002);
}

// Howell C-14 (perpendicular rectangles with a common edge, H = W = 1): 0.20004.
TEST(AnalyticScenes, PerpendicularPlates) {
    EXPECT_NEAR(plateFactor(test::assetPath("scenes/perpendicular_plates.gltf")),
                verify::kHowellC14, 0.002);
}

}  // namespace
}  // namespace daisy
