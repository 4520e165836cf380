// KHR_lights_punctual lights as direct sources (radiosity/punctual_lights.h). Oracles: the
// inverse-square cosine law for a point light over a plane, full shadow under a plate that
// covers the plane, the spot cone of KHR_lights_punctual's recommended falloff, and
// E_i = M_i H_i in the solved system.
#include "radiosity/punctual_lights.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "pipeline/session.h"
#include "spectral/fluorescence.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

// The plane y = 0, |x|, |z| <= 2, facing +y, as 8 x 8 quads.
TriangleMesh floorMesh() {
    TriangleMesh mesh;
    verify::addGrid(mesh, {-2, 0, 2}, {4, 0, 0}, {0, 0, -4}, 8, 8);
    return mesh;
}

PunctualLight pointLight(Vec3d position, double intensity = 1) {
    PunctualLight light;
    light.name = "bulb";
    light.position = position;
    light.intensity = intensity;
    return light;
}

TEST(PunctualLights, PointLightFollowsTheInverseSquareCosineLaw) {
    const PatchMesh patches = verify::patchesOf(floorMesh());
    ASSERT_EQ(patches.normals[0].y, 1.0);
    const Vec3d at{0.3, 2, -0.2};
    auto geometry = punctualLightGeometry(patches, {pointLight(at)});
    ASSERT_TRUE(geometry) << geometry.error().message;
    for (std::size_t i = 0; i < patches.patchCount(); ++i) {
        const Vec3d toLight = at - patches.centroids[i];
        const double d = length(toLight);
        EXPECT_NEAR(geometry->factors[i], (toLight.y / d) / (d * d), 1e-12) << i;
    }
}

TEST(PunctualLights, APlateBetweenLightAndFloorCastsFullShadow) {
    TriangleMesh mesh = floorMesh();
    const std::size_t floorPatches = mesh.triangleCount();
    verify::addQuad(mesh, {-3, 1, -3}, {3, 1, -3}, {3, 1, 3}, {-3, 1, 3});  // faces down
    const PatchMesh patches = verify::patchesOf(mesh);
    auto geometry = punctualLightGeometry(patches, {pointLight({0, 2, 0})});
    ASSERT_TRUE(geometry);
    for (std::size_t i = 0; i < floorPatches; ++i)
        EXPECT_EQ(geometry->factors[i], 0.0) << i;
}

TEST(PunctualLights, SpotConeFollowsTheRecommendedFalloff) {
    const PatchMesh patches = verify::patchesOf(floorMesh());
    PunctualLight spot = pointLight({0, 1, 0});
    spot.type = PunctualLight::Type::Spot;
    spot.direction = {0, -1, 0};
    spot.innerConeRad = 20 * std::numbers::pi / 180;
    spot.outerConeRad = 35 * std::numbers::pi / 180;
    auto geometry = punctualLightGeometry(patches, {spot});
    ASSERT_TRUE(geometry);
    int inside = 0, outside = 0;
    for (std::size_t i = 0; i < patches.patchCount(); ++i) {
        const Vec3d toLight = spot.position - patches.centroids[i];
        const double d = length(toLight);
        const double angle = std::acos(toLight.y / d);
        const double plain = (toLight.y / d) / (d * d);
        if (angle < spot.innerConeRad) {
            EXPECT_NEAR(geometry->factors[i], plain, 1e-12);
            ++inside;
        } else if (angle > spot.outerConeRad) {
            EXPECT_EQ(geometry->factors[i], 0.0);
            ++outside;
        } else {
            // (cos - cos outer) / (cos inner - cos outer), squared.
            const double t = (std::cos(angle) - std::cos(spot.outerConeRad)) /
                (std::cos(spot.innerConeRad) - std::cos(spot.outerConeRad));
            EXPECT_NEAR(geometry->factors[i], plain * t * t, 1e-9);
        }
    }
    EXPECT_GT(inside, 0);
    EXPECT_GT(outside, 0);
    EXPECT_DOUBLE_EQ(punctualFalloff(spot, 1, 1), 1.0);
}

TEST(PunctualLights, RangeWindowsTheInverseSquare) {
    PunctualLight light = pointLight({0, 0, 0});
    light.range = 2;
    EXPECT_DOUBLE_EQ(punctualFalloff(light, 1, 1), 1 - 1.0 / 16);  // 1 - (d / range)^4
    EXPECT_DOUBLE_EQ(punctualFalloff(light, 3, 1), 0.0);
}

TEST(PunctualLights, DirectLightIsReflectedIntoTheEmission) {
    // An open floor of reflectance 0.5 under a 4 cd white light: nothing else reflects, so
    // E_i = M_i H_i with H_i = g_i x the RGB emission spectrum of (4, 4, 4).
    Scene scene;
    scene.path = "lit floor";
    scene.mesh = floorMesh();
    Material grey;
    grey.name = "grey";
    grey.baseColor = {0.5, 0.5, 0.5};
    scene.materials = {grey};
    scene.lights = {pointLight({0, 2, 0}, 4)};
    SessionSettings settings;
    settings.backend = "cpu";
    settings.subdivideMaxEdge = 0;
    settings.logStages = false;
    auto session = Session::fromScene(scene, settings);
    ASSERT_TRUE(session) << session.error().message;
    const RadiositySystem& system = session->system();
    auto spectrum = materialEmission(session->wavelengths(), std::nullopt, Rgb{4, 4, 4}, "light");
    ASSERT_TRUE(spectrum);
    auto geometry = punctualLightGeometry(session->patches(), scene.lights);
    ASSERT_TRUE(geometry);
    const MaterialOperator& op = system.operators[system.patchOperator[0]];
    const std::size_t m = system.wavelengthCount;
    for (uint32_t i = 0; i < system.patchCount; ++i) {
        for (std::size_t k = 0; k < m; ++k) {
            EXPECT_NEAR(system.emission[i * m + k],
                        op.diagonal[k] * geometry->factors[i] * (*spectrum)[k], 1e-12)
                << i << ", " << k;
        }
    }
    EXPECT_GT(system.emission[0], 0.0);
}

TEST(PunctualLights, AUvLightOnAFluorescentFloorAddsTheUvSamples) {
    // `auto` adds UV samples when a UV emitter meets a fluorescent material (DESIGN.md
    // section 4): a black-light spectrum on a punctual light counts as a UV emitter.
    Scene scene;
    scene.path = "uv floor";
    scene.mesh = floorMesh();
    Material floor;
    floor.name = "fluorescent floor";
    floor.spectral.fluorescence = FluorophorePreset{"fluorescein"};
    scene.materials = {floor};
    PunctualLight light = pointLight({0, 2, 0}, 5);
    light.spectrum = SpectrumSpec{PresetSpectrum{"blacklight"}, 1.0};
    scene.lights = {light};
    SessionSettings settings;
    settings.backend = "cpu";
    settings.subdivideMaxEdge = 0;
    settings.logStages = false;
    auto session = Session::fromScene(scene, settings);
    ASSERT_TRUE(session) << session.error().message;
    EXPECT_LT(session->wavelengths().wavelengthNm(0), 400.0);
    // The fluorophore re-emits the absorbed UV in the visible: E has visible energy although
    // nothing but the UV light shines.
    const RadiositySystem& system = session->system();
    const std::size_t m = system.wavelengthCount;
    double visible = 0;
    for (std::size_t k = 0; k < m; ++k) {
        if (session->wavelengths().wavelengthNm(k) > 450) visible += system.emission[k];
    }
    EXPECT_GT(visible, 0.0);
}

}  // namespace
}  // namespace daisy
