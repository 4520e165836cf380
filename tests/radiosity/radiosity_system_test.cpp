// Assembly of E and the per-material M (radiosity_system.h) from a hand-built scene, against
// the spectral module's own functions (the oracle for sampling) and the dedup/flag rules.
#include "radiosity/radiosity_system.h"

#include <gtest/gtest.h>

#include "spectral/fluorescence.h"

namespace daisy {
namespace {

Material namedMaterial(const std::string& name, std::array<double, 3> baseColor) {
    Material material;
    material.name = name;
    material.origin = "test.gltf: materials[" + name + "]";
    material.baseColor = baseColor;
    return material;
}

// Four triangles, one per material 0..3 (materials 0 and 1 are identical).
Scene fourMaterialScene() {
    Scene scene;
    scene.path = "test.gltf";
    scene.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}};
    scene.mesh.triangles = {{0, 1, 2}, {1, 3, 2}, {0, 4, 1}, {1, 4, 5}};
    scene.mesh.materials = {0, 1, 2, 3};
    scene.materials.push_back(namedMaterial("white", {0.8, 0.8, 0.8}));
    scene.materials.push_back(namedMaterial("white_again", {0.8, 0.8, 0.8}));
    Material lamp = namedMaterial("lamp", {0, 0, 0});
    lamp.spectral.emission = SpectrumSpec{PresetSpectrum{"blacklight"}, 20};
    scene.materials.push_back(lamp);
    Material poster = namedMaterial("poster", {0.8, 0.8, 0.8});
    poster.spectral.fluorescence = FluorescenceSpec{FluorophorePreset{"fluorescein"}};
    scene.materials.push_back(poster);
    return scene;
}

TEST(RadiositySystem, AssemblesEmissionAndDeduplicatedOperators) {
    const Scene scene = fourMaterialScene();
    const PatchMesh patches = *buildPatchMesh(scene.mesh, 0);
    const WavelengthSet set = *WavelengthSet::fromWavelengths({360, 420, 480, 540, 600}, "test");
    auto system = buildRadiositySystem(scene, patches, set);
    ASSERT_TRUE(system.ok()) << system.error().message;
    ASSERT_EQ(system->patchCount, 4u);
    EXPECT_EQ(system->wavelengthCount, 5u);
    EXPECT_EQ(system->areas, patches.areas);
    // white and white_again share one operator; lamp (black) and poster have their own.
    ASSERT_EQ(system->operators.size(), 3u);
    EXPECT_EQ(system->patchOperator[0], system->patchOperator[1]);
    EXPECT_EQ(system->operators[0].materialNames,
              (std::vector<std::string>{"white", "white_again"}));
    const MaterialOperator& white = system->operators[system->patchOperator[0]];
    const MaterialOperator& lamp = system->operators[system->patchOperator[2]];
    const MaterialOperator& poster = system->operators[system->patchOperator[3]];
    EXPECT_TRUE(white.isDiagonal);
    EXPECT_FALSE(white.isZero);
    EXPECT_TRUE(lamp.isZero);  // baseColor 0: no gather needed
    EXPECT_FALSE(poster.isDiagonal);
    EXPECT_TRUE(system->hasFluorescence());
    // The poster's matrix is the spectral module's, untouched.
    const auto expectedPoster =
        materialReradiationMatrix(set, std::nullopt, {0.8, 0.8, 0.8},
                                  FluorescenceSpec{FluorophorePreset{"fluorescein"}}, "x");
    ASSERT_TRUE(expectedPoster.ok());
    EXPECT_EQ(poster.matrix.values, expectedPoster->values);
    // Largest power column sum <= 1 (validated matrices) and equal to rho for white.
    EXPECT_LE(poster.maxPowerGain, 1 + 1e-9);
    EXPECT_NEAR(white.maxPowerGain, *std::max_element(white.diagonal.begin(), white.diagonal.end()),
                1e-15);
    // Emission: the lamp's row is the bin-averaged blacklight x 20, the others zero.
    const auto lampEmission =
        materialEmission(set, SpectrumSpec{PresetSpectrum{"blacklight"}, 20}, {0, 0, 0}, "x");
    ASSERT_TRUE(lampEmission.ok());
    for (std::size_t k = 0; k < 5; ++k) {
        EXPECT_EQ(system->emissionRow(2)[k], (*lampEmission)[k]);
        EXPECT_EQ(system->emissionRow(0)[k], 0);
    }
    EXPECT_GT(system->emissionRow(2)[0], 0);  // 360 nm: the UV band
}

TEST(RadiositySystem, SceneFactsForTheAutoWavelengthSet) {
    Scene scene = fourMaterialScene();
    auto facts = sceneSpectralFacts(scene);
    ASSERT_TRUE(facts.ok());
    EXPECT_TRUE(facts->hasUvLights);
    EXPECT_TRUE(facts->hasFluorescence);
    // Auto then adds UV samples below the visible preset (wavelength_set.h).
    const WavelengthSet withUv =
        withUvExcitation(visibleWavelengths(), facts->hasUvLights, facts->hasFluorescence);
    EXPECT_LT(withUv.wavelengthNm(0), 400);

    scene.materials[3].spectral.fluorescence.reset();
    facts = sceneSpectralFacts(scene);
    ASSERT_TRUE(facts.ok());
    EXPECT_FALSE(facts->hasFluorescence);
    scene.materials[2].spectral.emission = SpectrumSpec{BlackbodySpectrum{2700}, 1};
    facts = sceneSpectralFacts(scene);
    EXPECT_FALSE(facts->hasUvLights);
}

TEST(RadiositySystem, BadMaterialIndexIsAnError) {
    Scene scene = fourMaterialScene();
    PatchMesh patches = *buildPatchMesh(scene.mesh, 0);
    patches.materials[1] = 9;
    auto system = buildRadiositySystem(scene, patches, visibleWavelengths());
    ASSERT_FALSE(system.ok());
    EXPECT_NE(system.error().message.find("patch 1 uses material 9"), std::string::npos);
}

}  // namespace
}  // namespace daisy
