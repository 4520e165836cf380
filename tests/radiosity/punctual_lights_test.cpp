// KHR_lights_punctual lights as direct sources (radiosity/punctual_lights.h). Oracles: the flux
// I Omega a point light puts on a square (the closed-form solid angle of a rectangle), at any
// height down to 1e-300 m; 4 pi I on the walls of a closed box; full shadow under a plate that
// covers the plane, and the gaps' share under tiles; the closed-form flux of KHR_lights_punctual's
// recommended spot cone and range window; and E_i = M_i H_i in the solved system.
#include "radiosity/punctual_lights.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <utility>

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

// The solid angle of the rectangle [x1, x2] x [z1, z2] of a plane seen from height h above its
// origin: the corner formula sum +-atan(x z / (h sqrt(x^2 + z^2 + h^2))) (each corner's term is
// the solid angle of the rectangle between the foot point and that corner, Howell B-3's
// companion for solid angles), in atan2 form so h = 1e-300 does not overflow.
double rectangleSolidAngle(double x1, double x2, double z1, double z2, double h) {
    const auto corner = [h](double x, double z) {
        return std::atan2(x * z, h * std::sqrt(x * x + z * z + h * h));
    };
    return corner(x2, z2) - corner(x1, z2) - corner(x2, z1) + corner(x1, z1);
}

// The light's flux over patches [first, last): sum g_i A_i (unit intensity).
double fluxOver(const PatchMesh& patches, const LightGeometry& geometry, std::size_t first,
                std::size_t last) {
    double flux = 0;
    for (std::size_t i = first; i < last; ++i)
        flux += geometry.factors[i] * patches.areas[i];
    return flux;
}

constexpr std::array<double, 6> kHeights = {2, 0.5, 5e-3, 1e-6, 1e-12, 1e-300};

TEST(PunctualLights, PointLightFluxIsTheSolidAngleOfEachSquare) {
    // Each grid cell (two patches) receives I x its solid angle, the corner formula, from any
    // height down to 1e-300 m: at a generic point, a grid vertex (the foot on four cells'
    // corners) and a cell's diagonal (the foot on the edge between its two triangles).
    const PatchMesh patches = verify::patchesOf(floorMesh());
    for (const double h : kHeights) {
        for (const auto& [x, z] : {std::pair{0.3, -0.2}, {0.0, 0.0}, {0.25, 0.25}}) {
            auto geometry = punctualLightGeometry(patches, {pointLight({x, h, z})});
            ASSERT_TRUE(geometry) << geometry.error().message;
            double total = 0;
            for (int row = 0; row < 8; ++row) {
                for (int column = 0; column < 8; ++column) {
                    // addGrid: cell (column, row) spans x in -2 + 0.5 [column, column + 1] and z
                    // in 2 - 0.5 [row + 1, row], patches 2 (8 row + column) and the next.
                    const double x1 = -2 + 0.5 * column - x, z1 = 2 - 0.5 * (row + 1) - z;
                    const double exact = rectangleSolidAngle(x1, x1 + 0.5, z1, z1 + 0.5, h);
                    const std::size_t first = 2 * std::size_t(8 * row + column);
                    EXPECT_NEAR(fluxOver(patches, *geometry, first, first + 2), exact,
                                1e-9 * exact + 1e-13)
                        << "h " << h << ", light at " << x << ", " << z << ", cell " << column
                        << ", " << row;
                    total += exact;
                }
            }
            EXPECT_NEAR(fluxOver(patches, *geometry, 0, patches.patchCount()), total, 1e-9 * total);
        }
    }
}

TEST(PunctualLights, FluxThroughASquareOnItsAxisIsISolidAngle) {
    // The a x a square of two patches (its centre on their shared diagonal) under a light on its
    // axis: I Omega, Omega = 4 asin(a^2 / (a^2 + 4 h^2)); the light's position is exact in double
    // at every height. Also the patch 5 mm under a light over its centroid, which the inverse
    // square law at the centroid gave 12,797 times the flux it can receive.
    TriangleMesh mesh;
    verify::addQuad(mesh, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1});
    const PatchMesh patches = verify::patchesOf(mesh);
    for (const double h : kHeights) {
        auto geometry = punctualLightGeometry(patches, {pointLight({0, h, 0}, 3)});
        ASSERT_TRUE(geometry) << geometry.error().message;
        // 4 asin(a^2 / (a^2 + 4 h^2)) at a = 2, written as the equal 4 atan((a / 2)^2 / (h
        // sqrt(h^2 + a^2 / 2))) (the corner formula), which keeps its precision at small h.
        const double omega = 4 * std::atan2(1, h * std::sqrt(h * h + 2));
        if (h > 1e-3) {
            EXPECT_NEAR(omega, 4 * std::asin(4 / (4 + 4 * h * h)), 1e-12);
        }
        EXPECT_NEAR(fluxOver(patches, *geometry, 0, 2), omega, 1e-12 * omega) << h;
        // By symmetry each triangle takes half.
        EXPECT_NEAR(geometry->factors[0] * patches.areas[0], omega / 2, 1e-12 * omega) << h;
        const Vec3d centroid = patches.centroids[0];
        auto offAxis = punctualLightGeometry(patches, {pointLight(centroid + Vec3d{0, h, 0})});
        ASSERT_TRUE(offAxis);
        const double exact = rectangleSolidAngle(-1 - centroid.x, 1 - centroid.x, -1 - centroid.z,
                                                 1 - centroid.z, h);
        EXPECT_NEAR(fluxOver(patches, *offAxis, 0, 2), exact, 1e-12 * exact) << h;
        EXPECT_LE(offAxis->factors[0] * patches.areas[0], 2 * std::numbers::pi);
    }
}

TEST(PunctualLights, EveryWattLandsOnTheWallsOfAClosedBox) {
    // A light anywhere inside a closed room, however close to a wall, edge or corner: the walls
    // receive exactly its 4 pi I (the solid angles of a closed surface seen from inside).
    const PatchMesh patches = verify::patchesOf(verify::unitCubeRoom(4));
    const double fourPi = 4 * std::numbers::pi;
    for (const double h : kHeights) {
        if (h >= 1) continue;
        for (const Vec3d at : {Vec3d{h, 0.37, 0.61}, Vec3d{h, 0.5, 0.5}, Vec3d{h, h, 0.61},
                               Vec3d{h, h, h}, Vec3d{0.37, 1 - h, 0.25}}) {
            if (at.y == 1) continue;  // 1 - 1e-300: the light is in the ceiling's plane
            auto geometry = punctualLightGeometry(patches, {pointLight(at)});
            ASSERT_TRUE(geometry) << geometry.error().message;
            EXPECT_NEAR(fluxOver(patches, *geometry, 0, patches.patchCount()), fourPi,
                        1e-9 * fourPi)
                << "light at " << at;
            for (std::size_t i = 0; i < patches.patchCount(); ++i)
                EXPECT_LE(geometry->factors[i] * patches.areas[i], 2 * std::numbers::pi) << i;
        }
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

// Tiles 0.49 m wide, 0.5 m apart, over a sheet 5 mm below cut into 3 m cells: the centroids of
// the sheet's patches' regions lie at multiples of 0.5 m, in the gaps between the tiles. Seen
// from a light 10 m above the middle, the sheet must get about the gaps' share of the flux it
// gets without the tiles (4% of the area), not the 100% those centroids would see.
TEST(PunctualLights, ASheetUnderGappedTilesGetsTheGapsShare) {
    TriangleMesh sheet;
    verify::addGrid(sheet, {0, -0.005, 12}, {12, 0, 0}, {0, 0, -12}, 4, 4);
    const std::size_t sheetPatches = sheet.triangleCount();
    TriangleMesh tiled = sheet;
    for (int a = 0; a < 24; ++a) {
        for (int b = 0; b < 24; ++b) {
            const double x = 0.5 * a + 0.005, z = 0.5 * b + 0.495;
            verify::addGrid(tiled, {x, 0, z}, {0.49, 0, 0}, {0, 0, -0.49}, 1, 1);
        }
    }
    const PunctualLight light = pointLight({6, 10, 6});
    const PatchMesh open = verify::patchesOf(sheet), covered = verify::patchesOf(tiled);
    auto bare = punctualLightGeometry(open, {light});
    auto under = punctualLightGeometry(covered, {light});
    ASSERT_TRUE(bare && under);
    const double all = fluxOver(open, *bare, 0, sheetPatches);
    EXPECT_NEAR(all, rectangleSolidAngle(-6, 6, -6, 6, 10.005), 1e-3 * all);
    const double gaps = fluxOver(covered, *under, 0, sheetPatches);
    EXPECT_LT(gaps, 0.12 * all);
}

// The flux of a light of unit intensity whose falloff is 1 inside the cone of half-angle
// `inner`, ((cos - cos outer) / (cos inner - cos outer))^2 out to `outer` and 0 beyond
// (KHR_lights_punctual's recommended spot falloff): 2 pi [(1 - cos inner) + (cos inner -
// cos outer) / 3], integrating the square over cos theta.
double spotConeFlux(double inner, double outer) {
    return 2 * std::numbers::pi * ((1 - std::cos(inner)) + (std::cos(inner) - std::cos(outer)) / 3);
}

TEST(PunctualLights, SpotPutsItsConesFluxOnTheFloorAtEveryHeight) {
    // A spot over a floor that catches its whole cone, pointing straight down and tilted by 25
    // degrees: the floor receives the cone's closed-form flux, from 0.5 m down to 1e-300 m (where
    // one patch sees the whole cone), and no patch more than I times its solid angle.
    const PatchMesh patches = verify::patchesOf(floorMesh());
    PunctualLight spot = pointLight({0.3, 1, -0.2});
    spot.type = PunctualLight::Type::Spot;
    spot.innerConeRad = 20 * std::numbers::pi / 180;
    spot.outerConeRad = 35 * std::numbers::pi / 180;
    const double exact = spotConeFlux(spot.innerConeRad, spot.outerConeRad);
    const double tilt = 25 * std::numbers::pi / 180;
    for (const Vec3d axis : {Vec3d{0, -1, 0}, Vec3d{std::sin(tilt), -std::cos(tilt), 0}}) {
        spot.direction = axis;
        for (const double h : kHeights) {
            if (h > 0.5) continue;  // the tilted cone's far edge must stay on the floor
            spot.position.y = h;
            auto geometry = punctualLightGeometry(patches, {spot});
            ASSERT_TRUE(geometry) << geometry.error().message;
            EXPECT_NEAR(fluxOver(patches, *geometry, 0, patches.patchCount()), exact, 0.002 * exact)
                << "h " << h << ", axis " << axis;
            for (std::size_t i = 0; i < patches.patchCount(); ++i) {
                const auto& c = patches.patches[i];
                const Triangle3d t{patches.positions[c[0]], patches.positions[c[1]],
                                   patches.positions[c[2]]};
                // (1e-15: the rounding of solid angles that are 0 in exact arithmetic.)
                EXPECT_LE(geometry->factors[i] * patches.areas[i],
                          frontSolidAngle(spot.position, t, patches.normals[i]) + 1e-15)
                    << i;
            }
        }
    }
    EXPECT_DOUBLE_EQ(punctualFalloff(spot, 1, 1), 1.0);
}

TEST(PunctualLights, SpotFalloffIsExactWhereAPatchLiesInsideOrOutsideTheCone) {
    // Far from the light (1 m over 0.5 m cells), a patch whose corners all lie inside the inner
    // cone gets exactly its solid angle; one whose every direction lies beyond the outer cone
    // gets nothing.
    const PatchMesh patches = verify::patchesOf(floorMesh());
    PunctualLight spot = pointLight({0, 1, 0});
    spot.type = PunctualLight::Type::Spot;
    spot.direction = {0, -1, 0};
    spot.innerConeRad = 30 * std::numbers::pi / 180;
    spot.outerConeRad = 35 * std::numbers::pi / 180;
    auto geometry = punctualLightGeometry(patches, {spot});
    ASSERT_TRUE(geometry);
    int inside = 0, outside = 0;
    for (std::size_t i = 0; i < patches.patchCount(); ++i) {
        const auto& c = patches.patches[i];
        const Triangle3d t{patches.positions[c[0]], patches.positions[c[1]],
                           patches.positions[c[2]]};
        double nearest = 1e9, farthest = 0;
        for (const Vec3d& p : t) {
            nearest = std::min(nearest, std::hypot(p.x, p.z));
            farthest = std::max(farthest, std::hypot(p.x, p.z));
        }
        const double g = geometry->factors[i] * patches.areas[i];
        if (farthest < std::tan(spot.innerConeRad)) {
            EXPECT_NEAR(g, frontSolidAngle(spot.position, t, patches.normals[i]), 1e-12) << i;
            ++inside;
        } else if (nearest > std::tan(spot.outerConeRad) + 0.5) {  // 0.5: a cell's width
            EXPECT_EQ(g, 0.0) << i;
            ++outside;
        }
    }
    EXPECT_GT(inside, 0);
    EXPECT_GT(outside, 0);
}

TEST(PunctualLights, RangeWindowsTheInverseSquare) {
    PunctualLight light = pointLight({0, 0, 0});
    light.range = 2;
    EXPECT_DOUBLE_EQ(punctualFalloff(light, 1, 1), 1 - 1.0 / 16);  // 1 - (d / range)^4
    EXPECT_DOUBLE_EQ(punctualFalloff(light, 3, 1), 0.0);
    // Over a plane that catches the whole window (range 1 at height h, q = h / range):
    // integral of (1 - (h / (mu range))^4) over mu = cos theta in [q, 1], times 2 pi:
    // 2 pi (1 - 4 q / 3 + q^4 / 3).
    const PatchMesh patches = verify::patchesOf(floorMesh());
    light.range = 1;
    for (const double h : kHeights) {
        if (h > 0.5) continue;
        light.position = {0.3, h, -0.2};
        auto geometry = punctualLightGeometry(patches, {light});
        ASSERT_TRUE(geometry);
        const double q = h;
        const double exact = 2 * std::numbers::pi * (1 - 4 * q / 3 + q * q * q * q / 3);
        EXPECT_NEAR(fluxOver(patches, *geometry, 0, patches.patchCount()), exact, 0.002 * exact)
            << h;
    }
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
