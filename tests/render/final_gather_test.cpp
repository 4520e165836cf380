// The direct final gather (image/final_gather.h) on parallel plates where the answer is known
// per point: a black source plate emitting E = 1 over a receiver of reflectance 0.5, nothing
// else, so the receiver's radiance at x is exactly rho E F(x -> source) / pi, F by Lambert's
// contour formula (verify/closed_forms.h), and the source's is E / pi. The smooth radiosity
// image (--gather none) cannot show that gradient within a patch; the gathered image must, to
// float precision. The path tracer must agree with it within its own noise. Patches lit by a
// punctual light are not gathered as sources.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <utility>
#include <vector>

#include "image/camera.h"
#include "image/final_gather.h"
#include "image/pixel_samples.h"
#include "image/radiosity_image.h"
#include "pathtrace/path_tracer.h"
#include "pipeline/session.h"
#include "radiosity/punctual_lights.h"
#include "verify/closed_forms.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

constexpr double kPi = std::numbers::pi;

Material flat(double reflectance, double emission) {
    return verify::flatMaterial(emission > 0 ? "source" : "receiver", reflectance, emission);
}

struct Plates {
    Scene scene;
    Camera camera;
    std::vector<Vec3d> source;  // the source square, counter-clockwise about its normal -z
};

Plates plates() {
    Plates p;
    p.scene.path = "plates";
    verify::addQuad(p.scene.mesh, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, 0);  // receiver
    p.source = {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}};
    verify::addQuad(p.scene.mesh, p.source[0], p.source[1], p.source[2], p.source[3], 1);
    p.scene.materials = {flat(0.5, 0), flat(0, 1)};
    p.camera.name = "oblique";
    p.camera.position = {0.5, -1.5, 0.6};
    p.camera.forward = normalize(Vec3d{0.5, 0.5, 0} - p.camera.position);
    const Vec3d side = normalize(cross(p.camera.forward, Vec3d{0, 0, 1}));
    p.camera.up = cross(side, p.camera.forward);
    p.camera.yFovRad = 0.9;
    return p;
}

Session solvedSession(const Plates& p) {
    SessionSettings settings;
    settings.subdivideMaxEdge = 0.25;
    settings.wavelengthsText = "550";
    settings.wavelengthSet = *WavelengthSet::fromWavelengths({550}, "550");
    settings.logStages = false;
    auto session = Session::fromScene(p.scene, settings);
    EXPECT_TRUE(session.ok()) << session.error().message;
    EXPECT_TRUE(session->buildFormFactors().ok());
    EXPECT_TRUE(session->solve().ok());
    return std::move(*session);
}

// The gathered image (--gather direct) at the default settings.
Expected<Image> gatheredImage(const Session& session, const Camera& camera, int width, int height) {
    RenderSettings settings;
    settings.width = width;
    settings.height = height;
    return renderRadiosityImage(session, camera, settings, GatherMode::Direct, {}, false);
}

// Where the ray through image position (x, y) meets the receiver's plane z = 0.
Vec3d onReceiverPlane(const Camera& camera, int width, int height, double x, double y) {
    const Ray ray = primaryRay(camera, width, height, x, y);
    const Vec3d o{ray.origin[0], ray.origin[1], ray.origin[2]};
    const Vec3d d{ray.direction[0], ray.direction[1], ray.direction[2]};
    return o + d * (-o.z / d.z);
}

bool insideReceiver(const Vec3d& p) {
    return p.x > 0.01 && p.x < 0.99 && p.y > 0.01 && p.y < 0.99;
}

// The receiver point the ray through pixel (x, y)'s centre hits, when the whole pixel (its four
// corners) lies on the receiver.
bool receiverPoint(const Camera& camera, int width, int height, int x, int y, Vec3d& point) {
    for (const auto& [dx, dy] : {std::pair{0, 0}, {1, 0}, {0, 1}, {1, 1}}) {
        if (!insideReceiver(onReceiverPlane(camera, width, height, x + dx, y + dy))) return false;
    }
    point = onReceiverPlane(camera, width, height, x + 0.5, y + 0.5);
    return true;
}

// A receiver image's error against a closed form per pixel (at the pixel centre's receiver
// point, pixels wholly on the receiver): relative RMS, and the ratio of the means.
struct ReceiverError {
    double rms = 0, meanRatio = 0;
    int pixels = 0;
};

ReceiverError receiverError(const Session& session, const Camera& camera, const Image& image,
                            const std::function<double(const Vec3d&)>& exact) {
    const double yWeight = session.wavelengths().xyzWeights(0)[1];
    double squares = 0, sum = 0, sumExact = 0;
    ReceiverError error;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            Vec3d point;
            if (!receiverPoint(camera, image.width, image.height, x, y, point)) continue;
            const double want = exact(point);
            const double value = image.at(x, y)[1] / yWeight;
            squares += (value - want) * (value - want) / (want * want);
            sum += value;
            sumExact += want;
            ++error.pixels;
        }
    }
    if (error.pixels > 0) {
        error.rms = std::sqrt(squares / error.pixels);
        error.meanRatio = sum / sumExact;
    }
    return error;
}

TEST(FinalGather, ParallelPlatesMatchThePointToPolygonClosedForm) {
    const Plates p = plates();
    Session session = solvedSession(p);
    RenderSettings settings;
    settings.width = 48;
    settings.height = 36;
    DirectLightSettings direct;
    auto gathered =
        renderRadiosityImage(session, p.camera, settings, GatherMode::Direct, direct, false);
    auto smooth =
        renderRadiosityImage(session, p.camera, settings, GatherMode::None, direct, false);
    ASSERT_TRUE(gathered.ok() && smooth.ok());
    const double yWeight = session.wavelengths().xyzWeights(0)[1];
    int checked = 0;
    double worstSmooth = 0;
    for (int y = 0; y < settings.height; ++y) {
        for (int x = 0; x < settings.width; ++x) {
            Vec3d point;
            if (!receiverPoint(p.camera, settings.width, settings.height, x, y, point)) continue;
            const double exact = 0.5 * verify::pointToPolygon(point, {0, 0, 1}, p.source) / kPi;
            EXPECT_NEAR(gathered->at(x, y)[1] / yWeight, exact, 2e-4 * exact + 1e-7)
                << x << " " << y;
            worstSmooth =
                std::max(worstSmooth, std::abs(smooth->at(x, y)[1] / yWeight - exact) / exact);
            ++checked;
        }
    }
    EXPECT_GT(checked, 60);
    // The oracle sees the difference: the smooth image is several percent off somewhere.
    EXPECT_GT(worstSmooth, 0.03);
}

// A double-sided source whose front faces away from the receiver (up, as an exporter may leave
// an emissive panel): its back face emits towards the receiver, in the solve and so in the
// gathered image, which must match the closed form of the source's downward face as above
// (with only the front faces as lights, every receiver pixel was 0).
TEST(FinalGather, TheBackOfADoubleSidedSourceIsGathered) {
    Plates p = plates();
    p.scene.mesh = {};
    verify::addQuad(p.scene.mesh, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, 0);
    verify::addQuad(p.scene.mesh, p.source[3], p.source[2], p.source[1], p.source[0], 1);
    p.scene.materials[1].doubleSided = true;
    const Session session = solvedSession(p);
    const auto gathered = gatheredImage(session, p.camera, 48, 36);
    ASSERT_TRUE(gathered.ok());
    const ReceiverError error = receiverError(session, p.camera, *gathered, [&](const Vec3d& x) {
        return 0.5 * verify::pointToPolygon(x, {0, 0, 1}, p.source) / kPi;
    });
    EXPECT_GT(error.pixels, 60);
    EXPECT_LT(error.rms, 2e-4);
    EXPECT_NEAR(error.meanRatio, 1, 2e-4);
}

// The per-patch estimate the viewer shows before F (patchDirectIrradiance): nothing between
// the plates, so every shadow segment is open and H at a receiver patch's centroid is exactly
// E F(centroid -> source) (E = 1); the source reflects nothing and gets none.
TEST(FinalGather, PatchDirectIrradianceIsThePointToPolygonFactorAtTheCentroid) {
    const Plates p = plates();
    SessionSettings settings;
    settings.subdivideMaxEdge = 0.25;
    settings.wavelengthSet = *WavelengthSet::fromWavelengths({550}, "550");
    settings.logStages = false;
    auto session = Session::fromScene(p.scene, settings);
    ASSERT_TRUE(session.ok()) << session.error().message;
    const PatchMesh& patches = session->patches();
    auto h = patchDirectIrradiance(p.scene, patches, session->system(), DirectLightSettings{});
    ASSERT_TRUE(h.ok()) << h.error().message;
    ASSERT_EQ(h->size(), patches.patchCount());
    int receivers = 0;
    for (uint32_t i = 0; i < patches.patchCount(); ++i) {
        if (patches.materials[i] == 1) {
            EXPECT_EQ((*h)[i], 0.0);
            continue;
        }
        const double exact = verify::pointToPolygon(patches.centroids[i], {0, 0, 1}, p.source);
        EXPECT_NEAR((*h)[i], exact, 1e-5 * exact) << i;
        ++receivers;
    }
    EXPECT_GE(receivers, 32);  // the unit square at edges <= 0.25
}

TEST(FinalGather, PathTracerAgreesWithTheGatheredPlates) {
    const Plates p = plates();
    Session session = solvedSession(p);
    const auto gathered = gatheredImage(session, p.camera, 16, 12);
    ASSERT_TRUE(gathered.ok());
    PathTraceSettings trace;
    trace.width = gathered->width;
    trace.height = gathered->height;
    trace.samplesPerPixel = 1024;
    trace.showProgress = false;
    auto traced = pathTrace(p.scene, session.wavelengths(), p.camera, trace);
    ASSERT_TRUE(traced.ok()) << traced.error().message;
    double sumGathered = 0, sumTraced = 0, variance = 0;
    for (int y = 0; y < gathered->height; ++y) {
        for (int x = 0; x < gathered->width; ++x) {
            Vec3d point;
            if (!receiverPoint(p.camera, gathered->width, gathered->height, x, y, point)) continue;
            sumGathered += gathered->at(x, y)[1];
            sumTraced += traced->image.at(x, y)[1];
            variance += *traced->varianceY.at(x, y);
        }
    }
    ASSERT_GT(sumGathered, 0);
    // Each pixel is a box-filtered mean in both (the path tracer jitters, the gather takes the
    // centre at 1 spp): a 0.5% allowance for that on top of five standard errors.
    EXPECT_NEAR(sumTraced, sumGathered, 5 * std::sqrt(variance) + 0.005 * sumGathered);
    EXPECT_LT(std::sqrt(variance), 0.01 * sumGathered);
}

// Per-pixel sample grids (edge-adaptive sampling, image/edge_sampling.h) change the shadow
// segments per sample from pixel to pixel: a black plate between the plates shadows every
// receiver point completely, so the gathered light must be exactly 0 in every pixel whatever
// the grids, 1 x 1 (16 segments) next to 8 x 8 (1 segment each), and still match the closed
// form on the open plates with the same grids.
TEST(FinalGather, PerPixelSampleGridsKeepShadowsAndTheClosedForm) {
    RenderSettings settings;
    settings.width = 32;
    settings.height = 24;
    std::vector<uint8_t> sides(std::size_t(settings.width) * settings.height);
    for (std::size_t i = 0; i < sides.size(); ++i)
        sides[i] = (i / 3) % 2 == 0 ? 8 : 1;  // three 8 x 8 pixels, three 1 x 1, ...
    settings.pixelSides = sides;
    DirectLightSettings direct;

    Plates shadowed = plates();
    // Under the source, over the receiver, facing it; below the camera's rays to the receiver.
    verify::addQuad(shadowed.scene.mesh, {-0.5, 0, 0.3}, {-0.5, 1.5, 0.3}, {1.5, 1.5, 0.3},
                    {1.5, 0, 0.3}, 2);
    shadowed.scene.materials.push_back(flat(0, 0));
    Session blocked = solvedSession(shadowed);
    auto dark = renderDirectLight(blocked.scene(), blocked.patches(), blocked.system(),
                                  blocked.wavelengths(), shadowed.camera, settings, direct, false);
    ASSERT_TRUE(dark.ok()) << dark.error().message;
    int receiverPixels = 0;
    for (int y = 0; y < settings.height; ++y) {
        for (int x = 0; x < settings.width; ++x) {
            Vec3d point;
            if (!receiverPoint(shadowed.camera, settings.width, settings.height, x, y, point))
                continue;
            EXPECT_EQ(dark->at(x, y)[1], 0.0f) << x << " " << y;
            ++receiverPixels;
        }
    }
    EXPECT_GT(receiverPixels, 20);

    const Plates open = plates();
    Session session = solvedSession(open);
    auto lit = renderDirectLight(session.scene(), session.patches(), session.system(),
                                 session.wavelengths(), open.camera, settings, direct, false);
    ASSERT_TRUE(lit.ok());
    const double yWeight = session.wavelengths().xyzWeights(0)[1];
    for (int y = 0; y < settings.height; ++y) {
        for (int x = 0; x < settings.width; ++x) {
            Vec3d point;
            if (!receiverPoint(open.camera, settings.width, settings.height, x, y, point)) continue;
            // The closed form's mean over the pixel's samples.
            const int side = sides[std::size_t(y * settings.width + x)];
            double exact = 0;
            for (int k = 0; k < side * side; ++k) {
                const auto [ox, oy] = sampleOffset(k, side);
                const Vec3d at =
                    onReceiverPlane(open.camera, settings.width, settings.height, x + ox, y + oy);
                exact += 0.5 * verify::pointToPolygon(at, {0, 0, 1}, open.source) / kPi;
            }
            exact /= side * side;
            EXPECT_NEAR(lit->at(x, y)[1] / yWeight, exact, 2e-4 * exact + 1e-7) << x << " " << y;
        }
    }
}

// The back of a one-sided surface neither emits nor reflects (the path tracer's model): seen
// from below, the receiver plate is black in every gather mode, and covered (not background),
// though its front's radiosity is not 0.
TEST(FinalGather, TheBackOfAOneSidedSurfaceIsBlack) {
    const Plates p = plates();
    const Session session = solvedSession(p);
    ASSERT_GT(session.solution().radiosity[0], 0.01);
    Camera below;
    below.name = "below";
    below.position = {0.5, 0.5, -1};
    below.forward = {0, 0, 1};
    below.up = {0, 1, 0};
    below.yFovRad = 0.4;
    RenderSettings settings;
    settings.width = 16;
    settings.height = 12;
    settings.edgeSamplesPerPixel = 4;
    for (const GatherMode mode : {GatherMode::None, GatherMode::Direct, GatherMode::Near}) {
        auto image = renderRadiosityImage(session, below, settings, mode, {}, false);
        ASSERT_TRUE(image.ok()) << image.error().message;
        for (int y = 0; y < settings.height; ++y) {
            for (int x = 0; x < settings.width; ++x) {
                const float* v = image->at(x, y);
                EXPECT_EQ(v[1], 0.0f) << gatherModeName(mode) << " " << x << " " << y;
                EXPECT_EQ(v[3], 1.0f) << gatherModeName(mode) << " " << x << " " << y;
            }
        }
    }
}

// A point light between the plates, with a source that also reflects (rho 0.5, E 1): the light
// it and the receiver reflect is in their E for the solve, but it is not light they emit, so the
// per-sample gather must not gather it from them; it gathers the point light itself at each
// sample instead: the gathered image with the light is the one without it plus exactly
// rho c I cos(theta) / (pi d^2) at each receiver pixel (one sample a pixel, at its centre),
// while the solved radiosity (the smooth part) changes too.
TEST(FinalGather, PunctualLightsAreGatheredPerSampleNotFromThePatchesTheyLight) {
    Plates p = plates();
    p.scene.materials[1] = flat(0.5, 1);
    const Session dark = solvedSession(p);
    PunctualLight bulb;
    bulb.name = "bulb";
    bulb.position = {0.5, 0.5, 0.5};
    bulb.intensity = 2;
    p.scene.lights = {bulb};
    const Session lit = solvedSession(p);
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    const DirectLightSettings direct;
    auto without = renderDirectLight(dark.scene(), dark.patches(), dark.system(),
                                     dark.wavelengths(), p.camera, settings, direct, false);
    auto with = renderDirectLight(lit.scene(), lit.patches(), lit.system(), lit.wavelengths(),
                                  p.camera, settings, direct, false);
    ASSERT_TRUE(without.ok() && with.ok());
    ASSERT_EQ(without->pixels.size(), with->pixels.size());
    auto spectra = punctualLightSpectra(lit.scene().lights, lit.wavelengths());
    ASSERT_TRUE(spectra.ok()) << spectra.error().message;
    const double spectrum = (*spectra)[0][0];  // c I at 550 nm
    ASSERT_GT(spectrum, 0);
    const double yWeight = lit.wavelengths().xyzWeights(0)[1];
    int pixels = 0;
    for (int y = 0; y < settings.height; ++y) {
        for (int x = 0; x < settings.width; ++x) {
            Vec3d point;
            if (!receiverPoint(p.camera, settings.width, settings.height, x, y, point)) continue;
            const Vec3d d = bulb.position - point;
            const double r = length(d);
            const double exact = 0.5 * spectrum * d.z / (r * r * r) / kPi;
            const double added = (with->at(x, y)[1] - without->at(x, y)[1]) / yWeight;
            EXPECT_NEAR(added, exact, 1e-5 * exact) << x << " " << y;
            ++pixels;
        }
    }
    EXPECT_GT(pixels, 100);
    // The light is in the solve: the receiver's radiosity rose.
    EXPECT_GT(lit.solution().radiosity[0], 1.5 * dark.solution().radiosity[0]);
}

// Penumbra refinement: a black plate under the source, at z = 0.9 with its edge at x = 0.5,
// hides the source's part x < x0 = p.x + (0.5 - p.x) / 0.9 from receiver point p, so the whole
// receiver is a penumbra of the source's two triangles and its exact radiance is
// rho F(p -> the source's part x > x0) / pi. Every pixel's neighbours have open and blocked
// segments to a triangle, so the second pass gives every pixel K segments instead of K / 16:
// the error per pixel must be what K segments give, well under what K / 16 give (measured at
// K = 64: 4.8% rms, 38% with the first pass alone), and the mean over the receiver unbiased
// (measured: 5e-5; weighting each light's open segments by area instead of by the kernel
// cos cos / r^2 made it 2% bright, which the bound of three standard errors, 0.6%, refuses).
// The gathered image of p's unit receiver (material 0, reflectance 0.5) under `sources`
// (material 1, E = 1, nothing between them and it) against the closed form sum over them of
// rho F(x -> source) / pi, seen from the plates' camera.
ReceiverError unoccludedSourcesError(Plates& p, const std::vector<std::vector<Vec3d>>& sources) {
    p.scene.materials = {flat(0.5, 0), flat(0, 1)};
    p.camera = plates().camera;
    Session session = solvedSession(p);
    RenderSettings settings;
    settings.width = 48;
    settings.height = 36;
    auto lit = renderDirectLight(session.scene(), session.patches(), session.system(),
                                 session.wavelengths(), p.camera, settings, {}, false);
    EXPECT_TRUE(lit.ok()) << lit.error().message;
    if (!lit) return {};
    return receiverError(session, p.camera, *lit, [&](const Vec3d& point) {
        double exact = 0;
        for (const auto& source : sources)
            exact += 0.5 * verify::pointToPolygon(point, {0, 0, 1}, source) / kPi;
        return exact;
    });
}

TEST(FinalGather, PenumbraPixelsTakeTheFullSegmentCountWithoutBias) {
    Plates p = plates();
    constexpr double kHeight = 0.9;
    verify::addQuad(p.scene.mesh, {-0.5, -0.5, kHeight}, {-0.5, 1.5, kHeight}, {0.5, 1.5, kHeight},
                    {0.5, -0.5, kHeight}, 2);
    p.scene.materials.push_back(flat(0, 0));
    Session session = solvedSession(p);
    RenderSettings settings;
    settings.width = 48;
    settings.height = 36;
    DirectLightSettings direct;  // K = 64
    auto lit = renderDirectLight(session.scene(), session.patches(), session.system(),
                                 session.wavelengths(), p.camera, settings, direct, false);
    ASSERT_TRUE(lit.ok()) << lit.error().message;
    const ReceiverError error = receiverError(session, p.camera, *lit, [](const Vec3d& point) {
        const double x0 = std::clamp(point.x + (0.5 - point.x) / kHeight, 0.0, 1.0);
        const std::vector<Vec3d> open = {{x0, 0, 1}, {x0, 1, 1}, {1, 1, 1}, {1, 0, 1}};
        return 0.5 * verify::pointToPolygon(point, {0, 0, 1}, open) / kPi;
    });
    ASSERT_GT(error.pixels, 60);
    const double rms = error.rms;
    EXPECT_LT(rms, 0.1);
    EXPECT_NEAR(error.meanRatio, 1.0, 3 * rms / std::sqrt(double(error.pixels)));
}

// Over 32 lights the draw's weights are a cheap stand-in and each segment carries its light's
// exact factor over it (importance sampling): not exact even where nothing is hidden, but
// unbiased. 36 small source squares (72 light triangles) over the receiver, nothing between:
// each pixel must be the closed form sum_l rho F(p -> l) / pi within the estimate's spread
// (K = 64 segments over 72 lights; measured 0.036% rms, not 0), and the mean over the
// receiver within 0.2% of it (measured 0.004%).
TEST(FinalGather, ManyLightsAreImportanceSampledWithoutBias) {
    Plates p;
    p.scene.path = "many lights";
    verify::addQuad(p.scene.mesh, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, 0);
    std::vector<std::vector<Vec3d>> sources;
    for (int a = 0; a < 6; ++a) {
        for (int b = 0; b < 6; ++b) {
            const double x0 = (a + 0.25) / 6, x1 = (a + 0.75) / 6;
            const double y0 = (b + 0.25) / 6, y1 = (b + 0.75) / 6;
            sources.push_back({{x0, y0, 1}, {x0, y1, 1}, {x1, y1, 1}, {x1, y0, 1}});
            verify::addQuad(p.scene.mesh, sources.back()[0], sources.back()[1], sources.back()[2],
                            sources.back()[3], 1);
        }
    }
    const ReceiverError error = unoccludedSourcesError(p, sources);
    ASSERT_GT(error.pixels, 60);
    const double rms = error.rms;
    EXPECT_LT(rms, 8e-4);  // 16 segments a pixel, as K / 4 gave, were 0.12%
    EXPECT_GT(rms, 0.0);  // not exact: the stand-in's weights are in play
    EXPECT_NEAR(error.meanRatio, 1.0, 0.002);
}

// Over 32 lights a run of a coplanar group of one emission is drawn as one by its stand-in,
// then a light in it by area: two discs, each a fan of 48 triangles (merged into fans of 46,
// drawn in runs of 32 and 14), one of them tilted. Every pixel must be the closed form over both
// discs (nothing between), within the estimate's spread, and the mean over the receiver within 0.2%
// of it (measured 0.004%): the draw's probabilities are the group's and the area's, or the image
// would be biased.
TEST(FinalGather, GroupsOfCoplanarLightsAreDrawnAsOneWithoutBias) {
    Plates p;
    p.scene.path = "two discs";
    verify::addQuad(p.scene.mesh, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, 0);
    constexpr int kRim = 48;
    std::vector<std::vector<Vec3d>> discs;  // counter-clockwise seen from the front (below)
    const auto addDisc = [&](const Vec3d& centre, double radius, double tiltRad) {
        std::vector<Vec3d> rim;
        for (int k = kRim; k-- > 0;) {  // clockwise seen from above
            const double a = 2 * kPi * k / kRim;
            const double x = radius * std::cos(a), y = radius * std::sin(a);
            rim.push_back(centre + Vec3d{x * std::cos(tiltRad), y, x * std::sin(tiltRad)});
        }
        const auto c = static_cast<uint32_t>(p.scene.mesh.positions.size());
        p.scene.mesh.positions.push_back(centre);
        p.scene.mesh.positions.insert(p.scene.mesh.positions.end(), rim.begin(), rim.end());
        for (uint32_t k = 0; k < kRim; ++k) {
            p.scene.mesh.triangles.push_back({c, c + 1 + k, c + 1 + (k + 1) % kRim});
            p.scene.mesh.materials.push_back(1);
        }
        discs.push_back(rim);
    };
    addDisc({0.28, 0.5, 1.0}, 0.22, 0.0);
    addDisc({0.78, 0.5, 1.0}, 0.14, -25.0 * kPi / 180);
    const ReceiverError error = unoccludedSourcesError(p, discs);
    ASSERT_GT(error.pixels, 60);
    const double rms = error.rms;
    EXPECT_LT(rms, 3e-3);  // measured 0.14%
    EXPECT_GT(rms, 0.0);
    EXPECT_NEAR(error.meanRatio, 1.0, 0.002);
}

}  // namespace
}  // namespace daisy
