// The path tracer's oracles: the white furnace (B = E / (1 - rho) everywhere in a
// closed room of one material), the fluorescent furnace (B = (I - M)^-1 E), a lit plane under
// an area light (the closed-form point-to-polygon irradiance, Howell B-3 and Lambert's formula),
// punctual lights over a plane (the inverse square cosine law), and a double-sided emitter and wall
// facing each other with their backs (the same closed forms, and the radiosity solve's mean against
// Howell C-11). Each check allows five standard errors of the estimator's own noise, and asserts
// that noise is small, so a wrong answer cannot hide in it.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "geometry/patch_mesh.h"
#include "image/origin_camera.h"
#include "pathtrace/path_tracer.h"
#include "pipeline/session.h"
#include "radiosity/punctual_lights.h"
#include "radiosity/radiosity_system.h"
#include "verify/closed_forms.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

constexpr double kPi = std::numbers::pi;

Camera lookAt(Vec3d from, Vec3d to, double yFovRad) {
    return test::lookAtCamera("test", from, to, {0, 1, 0}, yFovRad);
}
struct ImageMean {
    std::vector<double> channels;  // mean of each channel over the image
    double standardErrorY = 0;  // of the mean Y, from the per-pixel variances
};

// A 3 x 3 image of `spp` samples per pixel, no progress line: with a 0.003 rad field of view
// its pixels see one point.
PathTraceSettings pointSettings(int spp) {
    PathTraceSettings settings;
    settings.width = 3;
    settings.height = 3;
    settings.samplesPerPixel = spp;
    settings.showProgress = false;
    return settings;
}

ImageMean imageMean(const PathTraceResult& r) {
    ImageMean mean;
    const std::size_t pixels = std::size_t(r.image.width) * r.image.height;
    mean.channels.assign(std::size_t(r.image.channels), 0.0);
    double variance = 0;
    for (std::size_t p = 0; p < pixels; ++p) {
        for (int c = 0; c < r.image.channels; ++c)
            mean.channels[std::size_t(c)] += r.image.pixels[p * r.image.channels + c] / pixels;
        variance += r.varianceY.pixels[p];
    }
    mean.standardErrorY = std::sqrt(variance) / double(pixels);
    return mean;
}

// The furnace's exact radiance L = (I - M)^-1 E / pi by forward substitution (M is lower
// triangular, fluorescence.h), from the same sampled E and M the path tracer reads.
std::vector<double> furnaceRadiance(const Scene& scene, const WavelengthSet& set) {
    const PatchMesh patches = verify::patchesOf(scene.mesh);
    auto system = buildRadiositySystem(scene, patches, set);
    EXPECT_TRUE(system.ok());
    const ReradiationMatrix& m = system->operators[system->patchOperator[0]].matrix;
    std::vector<double> b(set.size());
    for (std::size_t o = 0; o < set.size(); ++o) {
        double rhs = system->emissionRow(0)[o];
        for (std::size_t k = 0; k < o; ++k)
            rhs += m(o, k) * b[k];
        b[o] = rhs / (1 - m(o, o));
    }
    for (double& v : b)
        v /= kPi;
    return b;
}

PathTraceResult traceFurnace(const Scene& scene, const WavelengthSet& set, int spp) {
    PathTraceSettings settings;
    settings.width = 12;
    settings.height = 9;
    settings.samplesPerPixel = spp;
    settings.spectral = true;
    settings.showProgress = false;
    auto r = pathTrace(scene, set, lookAt({0.5, 0.5, 0.9}, {0.4, 0.45, 0}, 1.4), settings);
    EXPECT_TRUE(r.ok()) << (r ? "" : r.error().message);
    return *r;
}

void expectFurnace(const Scene& scene, const WavelengthSet& set, double channelTolerance) {
    const PathTraceResult r = traceFurnace(scene, set, 1024);
    const std::vector<double> exact = furnaceRadiance(scene, set);
    const ImageMean mean = imageMean(r);
    const std::size_t m = set.size();
    for (std::size_t k = 0; k < m; ++k)
        EXPECT_NEAR(mean.channels[k], exact[k], channelTolerance * exact[k]) << set.wavelengthNm(k);
    const double exactY = set.toXyz(exact)[1];
    EXPECT_LT(mean.standardErrorY, 0.01 * exactY);  // noise small enough to see a 5% error
    EXPECT_NEAR(mean.channels[m + 1], exactY, 5 * mean.standardErrorY);
    EXPECT_NEAR(mean.channels[m + 3], 1.0, 1e-6);  // every sample hits the closed room
}

Scene furnaceScene(const Material& material) {
    Scene scene;
    scene.path = "furnace";
    scene.mesh = verify::unitCubeRoom(2);
    scene.materials = {material};
    return scene;
}

TEST(PathTracer, WhiteFurnaceIsEOverOneMinusRho) {
    const Scene scene = furnaceScene(verify::flatMaterial("flat", 0.6, 1.0));
    auto set = WavelengthSet::fromWavelengths({450, 550, 650}, "three");
    ASSERT_TRUE(set.ok());
    expectFurnace(scene, *set, 0.02);
    // The closed form itself: E / (1 - rho) / pi with E = 1, rho = 0.6.
    EXPECT_NEAR(furnaceRadiance(scene, *set)[1], 1 / (0.4 * kPi), 1e-12);
}

TEST(PathTracer, FluorescentFurnaceIsInverseOfIMinusM) {
    Material material = verify::flatMaterial("flat", 0.3, 1.0);
    material.spectral.fluorescence = FluorescenceSpec{FluorophorePreset{"fluorescein"}};
    const Scene scene = furnaceScene(material);
    auto set = WavelengthSet::fromWavelengths(
        {400, 420, 440, 460, 480, 500, 520, 540, 560, 580, 600, 620, 640}, "13");
    ASSERT_TRUE(set.ok());
    // The oracle must see the fluorescence: somewhere (I - M)^-1 E is far from E / (1 - rho).
    const std::vector<double> exact = furnaceRadiance(scene, *set);
    double largest = 0;
    for (double v : exact)
        largest = std::max(largest, v / (1 / (0.7 * kPi)) - 1);
    EXPECT_GT(largest, 0.1);
    expectFurnace(scene, *set, 0.03);
}

// The floor (material 0, reflectance 0.5) of `scene` under the emitting `square` (E = 1, black)
// at two points, 16,384 samples each: its radiance is rho E F(p -> square) / pi, F by Lambert's
// contour formula, within 5 standard errors, which stay under `noise` of it.
void expectFloorLitBy(const Scene& scene, const std::vector<Vec3d>& square, double noise) {
    auto set = WavelengthSet::fromWavelengths({550}, "one");
    ASSERT_TRUE(set.ok());
    const PathTraceSettings settings = pointSettings(16384);
    for (const Vec3d target : {Vec3d{0, 0, 0}, Vec3d{0.8, 0, 0.3}}) {
        auto r =
            pathTrace(scene, *set, lookAt(target + Vec3d{1.5, 0.6, 0.2}, target, 0.003), settings);
        ASSERT_TRUE(r.ok()) << r.error().message;
        const double f = verify::pointToPolygon(target, {0, 1, 0}, square);
        const double exactY = 0.5 * 1 * f / kPi;  // one sample at 550 nm: Y = L * ybar weight
        // The 3 x 3 pixels see the same point to 1e-5 (a 0.003 rad field): their mean.
        const ImageMean mean = imageMean(*r);
        const double y = mean.channels[1] / set->xyzWeights(0)[1];
        const double se = mean.standardErrorY / set->xyzWeights(0)[1];
        EXPECT_LT(se, noise * exactY);
        EXPECT_NEAR(y, exactY, 5 * se + 1e-4 * exactY) << target;
    }
}

// A unit square emitter (E = 1, black) at height 1 facing down over a floor of reflectance 0.5:
// the floor's radiance at p is rho E F(p -> square) / pi, F by Lambert's contour formula.
TEST(PathTracer, LitPlaneMatchesPointToPolygonIrradiance) {
    Scene scene;
    scene.path = "lit plane";
    verify::addQuad(scene.mesh, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}, {-10, 0, -10}, 0);
    const std::vector<Vec3d> square = {
        {-0.5, 1, -0.5}, {0.5, 1, -0.5}, {0.5, 1, 0.5}, {-0.5, 1, 0.5}};
    verify::addQuad(scene.mesh, square[0], square[1], square[2], square[3], 1);
    scene.materials = {verify::flatMaterial("flat", 0.5, 0), verify::flatMaterial("flat", 0, 1)};
    expectFloorLitBy(scene, square, 0.002);
    // The centre point is Howell B-3 four times over.
    EXPECT_NEAR(verify::pointToPolygon({0, 0, 0}, {0, 1, 0}, square),
                4 * verify::pointToRectangleCorner(0.5, 0.5, 1), 1e-12);
}

// The same square tessellated into 1,152 triangles (more than one group of emitters: the pick
// draws a group of about 37 neighbours, then a triangle of it) and 200 small far emitters behind
// the floor's plane, which cannot light it: the floor's radiance is still rho E F / pi.
TEST(PathTracer, ManyEmitterTrianglesAreDrawnInGroupsWithoutBias) {
    Scene scene;
    scene.path = "tessellated light";
    verify::addQuad(scene.mesh, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}, {-10, 0, -10}, 0);
    constexpr int kSide = 24;
    for (int a = 0; a < kSide; ++a) {
        for (int b = 0; b < kSide; ++b) {
            const double x0 = -0.5 + double(a) / kSide, x1 = -0.5 + double(a + 1) / kSide;
            const double z0 = -0.5 + double(b) / kSide, z1 = -0.5 + double(b + 1) / kSide;
            verify::addQuad(scene.mesh, {x0, 1, z0}, {x1, 1, z0}, {x1, 1, z1}, {x0, 1, z1}, 1);
        }
    }
    for (int k = 0; k < 100; ++k) {  // under the floor, facing down: never lights it
        const double x = -5 + 0.1 * k;
        verify::addQuad(scene.mesh, {x, -1, 0}, {x + 0.05, -1, 0}, {x + 0.05, -1, 0.05},
                        {x, -1, 0.05}, 1);
    }
    const std::vector<Vec3d> square = {
        {-0.5, 1, -0.5}, {0.5, 1, -0.5}, {0.5, 1, 0.5}, {-0.5, 1, 0.5}};
    scene.materials = {verify::flatMaterial("flat", 0.5, 0), verify::flatMaterial("flat", 0, 1)};
    expectFloorLitBy(scene, square, 0.01);
}

// A point light and a spot over an open floor of reflectance 0.5: nothing else reflects, so the
// floor's radiance at p is rho sum_l I_l cos(theta_l) falloff_l / d_l^2 / pi, the inverse square
// cosine law with KHR_lights_punctual's spot falloff. A light 1e-300 m over the floor leaves every
// pixel finite.
TEST(PathTracer, PunctualLightsFollowTheInverseSquareCosineLaw) {
    Scene scene;
    scene.path = "lit floor";
    verify::addQuad(scene.mesh, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}, {-10, 0, -10}, 0);
    scene.materials = {verify::flatMaterial("flat", 0.5, 0)};
    const SpectrumSpec flat{TabulatedSpectrum{{300, 900}, {1, 1}}, 1.0};
    PunctualLight bulb;
    bulb.name = "bulb";
    bulb.position = {0.3, 1, -0.2};
    bulb.intensity = 2;
    bulb.spectrum = flat;
    PunctualLight spot = bulb;
    spot.name = "spot";
    spot.type = PunctualLight::Type::Spot;
    spot.position = {0, 1.5, 0};
    spot.direction = {0, -1, 0};
    spot.intensity = 3;
    spot.innerConeRad = 20 * kPi / 180;
    spot.outerConeRad = 35 * kPi / 180;
    scene.lights = {bulb, spot};
    auto set = WavelengthSet::fromWavelengths({550}, "one");
    ASSERT_TRUE(set.ok());
    PathTraceSettings settings = pointSettings(4);
    for (const Vec3d target : {Vec3d{0, 0, 0}, Vec3d{1.5 * std::tan(27 * kPi / 180), 0, 0}}) {
        auto r =
            pathTrace(scene, *set, lookAt(target + Vec3d{1.5, 0.6, 0.2}, target, 0.003), settings);
        ASSERT_TRUE(r.ok()) << r.error().message;
        double irradiance = 0;
        for (const PunctualLight& light : scene.lights) {
            const Vec3d d = light.position - target;
            const double r2 = dot(d, d), cosine = d.y / std::sqrt(r2);
            irradiance += light.intensity * cosine / r2 *
                punctualFalloff(light, std::sqrt(r2), -dot(light.direction, d) / std::sqrt(r2));
        }
        const double y = imageMean(*r).channels[1] / set->xyzWeights(0)[1];
        EXPECT_NEAR(y, 0.5 * irradiance / kPi, 1e-4 * y) << target;
    }
    // The second target lies in the spot's falloff band: (cos 27 - cos 35) / (cos 20 - cos 35)
    // = 0.596, squared 0.355.
    EXPECT_NEAR(punctualFalloff(spot, 1, std::cos(27 * kPi / 180)), 0.3554, 1e-4);

    scene.lights = {bulb};
    scene.lights[0].position = {0.1, 1e-300, 0.1};
    settings.width = 16;
    settings.height = 16;
    auto r = pathTrace(scene, *set, lookAt({0.1, 1, 0.6}, {0.1, 0, 0.1}, 0.5), settings);
    ASSERT_TRUE(r.ok());
    for (const float v : r->image.pixels)
        EXPECT_TRUE(std::isfinite(v));
}

// A double-sided emitter (the unit square at z = 1, front facing +z, E = 1, black) and a
// double-sided wall (the unit square at z = 0, front facing -z, reflectance 0.5) that face each
// other only with their backs, which glTF doubleSided makes surfaces too (back patches).
Scene facingBacks(bool doubleSided) {
    Scene scene;
    scene.path = "facing backs";
    verify::addGrid(scene.mesh, {0, 0, 0}, {0, 1, 0}, {1, 0, 0}, 4, 4, 0);  // faces -z
    verify::addGrid(scene.mesh, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, 4, 4, 1);  // faces +z
    Material wall = verify::flatMaterial("wall", 0.5, 0), lamp = verify::flatMaterial("lamp", 0, 1);
    wall.doubleSided = lamp.doubleSided = doubleSided;
    scene.materials = {wall, lamp};
    return scene;
}

// Both integrators against closed forms on facingBacks: the path tracer's radiance at points of
// the wall's back is rho E F(p -> emitter) / pi (Lambert's point-to-polygon factor) and the
// emitter's back shows E / pi; the radiosity solve's mean over the wall's back patches is rho E F
// with F Howell C-11 (unit squares at distance 1). One-sided, the wall and the emitter's back
// are black in both.
TEST(PathTracer, DoubleSidedSurfacesEmitAndReflectOnBothFacesAsRadiosityDoes) {
    auto set = WavelengthSet::fromWavelengths({550}, "one");
    ASSERT_TRUE(set.ok());
    const std::vector<Vec3d> lamp = {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    PathTraceSettings settings = pointSettings(16384);
    const double ybar = set->xyzWeights(0)[1];
    for (const bool doubleSided : {true, false}) {
        const Scene scene = facingBacks(doubleSided);
        settings.samplesPerPixel = doubleSided ? 16384 : 16;  // one-sided, every sample is 0
        // Points of the wall, seen from between the squares.
        for (const Vec3d target : {Vec3d{0.5, 0.5, 0}, Vec3d{0.2, 0.7, 0}}) {
            auto r = pathTrace(scene, *set, lookAt(target + Vec3d{0.3, 0.1, 0.45}, target, 0.003),
                               settings);
            ASSERT_TRUE(r.ok()) << r.error().message;
            const double exact =
                doubleSided ? 0.5 * verify::pointToPolygon(target, {0, 0, 1}, lamp) / kPi : 0.0;
            const ImageMean mean = imageMean(*r);
            const double se = mean.standardErrorY / ybar;
            EXPECT_LT(se, 0.002 * std::max(exact, 0.01));
            EXPECT_NEAR(mean.channels[1] / ybar, exact, 5 * se + 1e-4 * exact)
                << target << (doubleSided ? " double-sided" : " one-sided");
        }
        // The emitter's back: E / pi, no reflection.
        const Vec3d onLamp{0.4, 0.6, 1};
        auto r = pathTrace(scene, *set, lookAt(onLamp + Vec3d{0.2, -0.1, -0.45}, onLamp, 0.003),
                           settings);
        ASSERT_TRUE(r.ok());
        EXPECT_NEAR(imageMean(*r).channels[1] / ybar, doubleSided ? 1 / kPi : 0.0,
                    1e-6);  // float pixels

        SessionSettings session;
        session.backend = "cpu";
        session.subdivideMaxEdge = 0;
        session.wavelengthSet = *set;
        session.formFactors.progress = false;
        session.logStages = false;
        auto radiosity = Session::fromScene(scene, session);
        ASSERT_TRUE(radiosity.ok()) << radiosity.error().message;
        ASSERT_TRUE(radiosity->solve().ok());
        const PatchMesh& patches = radiosity->patches();
        const std::vector<double>& b = radiosity->solution().radiosity;
        double flux = 0, area = 0;
        for (uint32_t i = 0; i < 32; ++i) {  // the wall's 32 front patches
            if (patches.backPatch[i] != kNoBackPatch)
                flux += b[patches.backPatch[i]] * patches.areas[i];
            area += patches.areas[i];
        }
        EXPECT_NEAR(flux / area, doubleSided ? 0.5 * verify::kHowellC11 : 0.0,
                    0.005 * verify::kHowellC11);
    }
}

// The variance estimate follows 1 / n. (Not in the furnace: there the emitters touch the
// receivers, cos cos / r^2 has infinite variance near the room's edges, and small-n estimates of
// it run low.)
TEST(PathTracer, DeterministicSeedsAndNoiseFallsAsOneOverRootN) {
    Scene scene;
    scene.path = "lit plane";
    verify::addQuad(scene.mesh, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}, {-10, 0, -10}, 0);
    verify::addQuad(scene.mesh, {-0.5, 1, -0.5}, {0.5, 1, -0.5}, {0.5, 1, 0.5}, {-0.5, 1, 0.5}, 1);
    scene.materials = {verify::flatMaterial("flat", 0.5, 0), verify::flatMaterial("flat", 0, 1)};
    auto set = WavelengthSet::fromWavelengths({550}, "one");
    ASSERT_TRUE(set.ok());
    PathTraceSettings settings;
    settings.width = 8;
    settings.height = 6;
    settings.samplesPerPixel = 64;
    settings.showProgress = false;
    const Camera camera = lookAt({2, 1.5, 0}, {0, 0, 0}, 0.6);
    auto a = pathTrace(scene, *set, camera, settings);
    auto b = pathTrace(scene, *set, camera, settings);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->image.pixels, b->image.pixels);
    settings.seed = 2;
    auto other = pathTrace(scene, *set, camera, settings);
    ASSERT_TRUE(other.ok());
    EXPECT_NE(a->image.pixels, other->image.pixels);
    settings.samplesPerPixel = 1024;
    auto c = pathTrace(scene, *set, camera, settings);
    ASSERT_TRUE(c.ok());
    EXPECT_GT(a->relativeNoise, 0.01);
    // 16x the samples: a quarter of the noise (within the noise of the noise estimate).
    EXPECT_NEAR(c->relativeNoise / a->relativeNoise, 0.25, 0.03);
}

TEST(PathTracer, RefusesBadSettings) {
    const Scene scene = furnaceScene(verify::flatMaterial("flat", 0.5, 1.0));
    PathTraceSettings settings;
    settings.width = 0;
    auto r =
        pathTrace(scene, fineWavelengths(), lookAt({0.5, 0.5, 0.5}, {0, 0.5, 0.5}, 1), settings);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("must all be positive"), std::string::npos);
}

}  // namespace
}  // namespace daisy
