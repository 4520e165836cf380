// The session (pipeline/session.h): F is built once and reused across material and wavelength
// edits (checked by the session's build counter, not by timing), warm starts, cancellation, and
// the disk cache reached through the session.
#include "pipeline/session.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <numbers>
#include <utility>
#include <vector>

#include "radiosity/matrix_transport.h"
#include "test_util.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

const std::string kCornellBox = test::assetPath("scenes/cornell_box.gltf");

// The Cornell box at 920 patches on the cpu backend, solved to 1e-6 (so iteration counts are
// large enough to compare), without a disk cache unless `cache` is given.
SessionSettings cornellSettings(std::optional<std::filesystem::path> cache = std::nullopt) {
    SessionSettings settings;
    settings.scenePath = kCornellBox;
    settings.backend = "cpu";
    settings.subdivideMaxEdge = 0.1;
    settings.formFactors.progress = false;
    settings.solver.tolerance = 1e-6;
    settings.cacheDirectory = cache;
    settings.logStages = false;
    return settings;
}

Session openOk(SessionSettings settings) {
    auto session = Session::open(std::move(settings));
    EXPECT_TRUE(session.ok()) << (session.ok() ? "" : session.error().message);
    return std::move(*session);
}

std::size_t materialIndex(const Session& session, const std::string& name) {
    const auto& materials = session.scene().materials;
    for (std::size_t i = 0; i < materials.size(); ++i)
        if (materials[i].name == name) return i;
    ADD_FAILURE() << "no material " << name;
    return 0;
}

// Every factor of `a` equals `b`'s bit for bit, over the union of their stored entries.
void expectSameFactors(const Transport& a, const Transport& b) {
    auto compared = a.compare(b, {});
    ASSERT_TRUE(compared.ok()) << compared.error().message;
    EXPECT_GT(compared->unionEntries, 0u);
    EXPECT_EQ(compared->onlyInA, 0u);
    EXPECT_EQ(compared->onlyInB, 0u);
    EXPECT_EQ(compared->maxAbsolute.absolute, 0.0);
}

// Mean reflected luminance Y of the patches of material `index`.
double meanY(const Session& session, std::size_t index) {
    const std::vector<Xyz> xyz = session.patchRadianceXyz();
    double sum = 0, area = 0;
    for (uint32_t i = 0; i < session.patches().patchCount(); ++i) {
        if (session.patches().materials[i] != index) continue;
        sum += session.patches().areas[i] * xyz[i][1];
        area += session.patches().areas[i];
    }
    return area > 0 ? sum / area : 0;
}

// Editing a material rebuilds E and M only: F is built exactly once, the re-solve starts warm
// and lands on the answer a fresh session with the edited material computes from scratch.
// `auto`: the links from 2 GiB of estimated F on, or where F does not fit, and only where the
// cpu backend evaluates them.
TEST(Session, AutoTransportTakesTheLinksWhereTheMatrixIsLargeOrDoesNotFit) {
    const uint64_t gib = uint64_t(1) << 30, roomy = 16 * gib, half = 2 * gib;
    EXPECT_EQ(chooseTransport(half - 1, roomy, "auto"), TransportKind::Matrix);
    EXPECT_EQ(chooseTransport(half, roomy, "auto"), TransportKind::Hierarchical);
    EXPECT_EQ(chooseTransport(half, roomy, "cpu"), TransportKind::Hierarchical);
    EXPECT_EQ(chooseTransport(64 << 20, 32 << 20, "cpu"), TransportKind::Hierarchical);
    EXPECT_EQ(chooseTransport(64 << 20, 64 << 20, "cpu"), TransportKind::Matrix);
    for (const char* backend : {"reference", "vulkan", "cuda"})
        EXPECT_EQ(chooseTransport(2 * gib, gib, backend), TransportKind::Matrix) << backend;
}

TEST(Session, MaterialEditResolvesWithoutRebuildingF) {
    Session session = openOk(cornellSettings());
    ASSERT_TRUE(session.solve().ok());
    EXPECT_EQ(session.formFactorBuildCount(), 1u);
    const std::size_t white = materialIndex(session, "white");
    const double before = meanY(session, white);

    Material darker = session.scene().materials[white];
    darker.spectral.reflectance.reset();
    darker.baseColor = {0.2, 0.2, 0.2};
    ASSERT_TRUE(session.setMaterial(white, darker).ok());
    auto warm = session.solve();
    ASSERT_TRUE(warm.ok()) << warm.error().message;
    EXPECT_EQ(session.formFactorBuildCount(), 1u);
    EXPECT_TRUE(warm->converged);
    const double after = meanY(session, white);
    EXPECT_LT(after, 0.5 * before);  // reflectance 0.2 instead of ~0.75: far darker walls

    // The oracle: a cold solve of the edited scene in a fresh session (its own F, same seed).
    Session fresh = openOk(cornellSettings());
    ASSERT_TRUE(fresh.setMaterial(white, darker).ok());
    ASSERT_TRUE(fresh.solve().ok());
    const auto& a = session.solution().radiosity;
    const auto& b = fresh.solution().radiosity;
    ASSERT_EQ(a.size(), b.size());
    double diff = 0, norm = 0;
    for (std::size_t k = 0; k < a.size(); ++k) {
        diff += std::abs(a[k] - b[k]);
        norm += std::abs(b[k]);
    }
    EXPECT_LT(diff / norm, 1e-5);  // both within the 1e-6 residual of the same solution
}

// A punctual light edited in place: twice the intensity is twice its direct light in E (the
// shadow rays are not traced again), a moved light is traced again, and the warm solve matches
// a session opened with the edited light.
TEST(Session, LightEditRecomputesItsDirectLight) {
    Scene scene = verify::unitRoomScene(2, "D65");
    PunctualLight lamp;
    lamp.name = "lamp";
    lamp.position = Vec3d{0.5, 0.7, 0.5};
    lamp.intensity = 0.5;
    scene.lights.push_back(lamp);
    SessionSettings settings;
    settings.backend = "cpu";
    settings.subdivideMaxEdge = 0;
    settings.formFactors.progress = false;
    settings.logStages = false;
    settings.solver.tolerance = 1e-8;
    auto session = Session::fromScene(scene, settings);
    ASSERT_TRUE(session) << session.error().message;
    ASSERT_TRUE(session->solve());
    const std::vector<double> before = session->system().punctualEmission;
    ASSERT_FALSE(before.empty());
    PunctualLight brighter = lamp;
    brighter.intensity = 1.0;
    ASSERT_TRUE(session->setLight(0, brighter));
    const std::vector<double>& after = session->system().punctualEmission;
    ASSERT_EQ(after.size(), before.size());
    for (std::size_t k = 0; k < after.size(); ++k)
        EXPECT_NEAR(after[k], 2 * before[k], 1e-12 * (1 + before[k])) << k;
    ASSERT_TRUE(session->solve());

    Scene edited = scene;
    edited.lights[0] = brighter;
    auto fresh = Session::fromScene(edited, settings);
    ASSERT_TRUE(fresh);
    ASSERT_TRUE(fresh->solve());
    const auto& a = session->solution().radiosity;
    const auto& b = fresh->solution().radiosity;
    ASSERT_EQ(a.size(), b.size());
    double diff = 0, norm = 0;
    for (std::size_t k = 0; k < a.size(); ++k) {
        diff += std::abs(a[k] - b[k]);
        norm += std::abs(b[k]);
    }
    EXPECT_LT(diff / norm, 1e-6);

    // Moved towards the floor: the floor's share of the direct light grows.
    PunctualLight lower = brighter;
    lower.position = Vec3d{0.5, 0.2, 0.5};
    ASSERT_TRUE(session->setLight(0, lower));
    double floorBefore = 0, floorAfter = 0;
    const std::size_t m = session->wavelengths().size();
    const PatchMesh& patches = session->patches();
    for (std::size_t p = 0; p < patches.patchCount(); ++p) {
        if (patches.normals[p].y < 0.5) continue;  // the floor faces +y
        for (std::size_t k = 0; k < m; ++k) {
            floorBefore += 2 * before[p * m + k];
            floorAfter += session->system().punctualEmission[p * m + k];
        }
    }
    EXPECT_GT(floorAfter, 2 * floorBefore);
    EXPECT_FALSE(session->setLight(7, lower));
}

// Warm start: after a small edit, starting from the last B takes fewer iterations than from E,
// for every solver.
TEST(Session, WarmStartConvergesInFewerIterationsThanCold) {
    for (SolverKind kind : {SolverKind::GaussSeidel, SolverKind::Jacobi, SolverKind::Southwell}) {
        SessionSettings settings = cornellSettings();
        settings.solver.kind = kind;
        Session session = openOk(settings);
        ASSERT_TRUE(session.solve().ok());
        const std::size_t red = materialIndex(session, "red");
        Material edited = session.scene().materials[red];
        edited.spectral.reflectance.reset();
        edited.baseColor = {0.6, 0.1, 0.1};
        ASSERT_TRUE(session.setMaterial(red, edited).ok());

        auto warm = session.solve();
        ASSERT_TRUE(warm.ok());
        SolveRequest coldRequest;
        coldRequest.warmStart = false;
        auto cold = session.solve(coldRequest);
        ASSERT_TRUE(cold.ok());
        EXPECT_TRUE(warm->converged && cold->converged) << solverKindName(kind);
        EXPECT_LT(warm->iterations, cold->iterations) << solverKindName(kind);
        EXPECT_EQ(session.formFactorBuildCount(), 1u);
    }
}

// Cancellation: a token cancelled during the second iteration stops the solve there, with the
// status set and the last iterate kept (finite), and no error.
TEST(Session, CancelledSolveReturnsPromptlyWithStatus) {
    Session session = openOk(cornellSettings());
    ASSERT_TRUE(session.buildFormFactors().ok());
    CancelToken token;
    SolveRequest request;
    request.cancel = &token;
    request.onIteration = [&](int iteration, std::span<const double>) {
        if (iteration == 2) token.cancel();
    };
    auto solved = session.solve(request);
    ASSERT_TRUE(solved.ok()) << solved.error().message;
    EXPECT_TRUE(solved->cancelled);
    EXPECT_FALSE(solved->converged);
    EXPECT_EQ(solved->iterations, 2);
    EXPECT_NE(solved->warning.find("cancelled"), std::string::npos) << solved->warning;
    for (double b : solved->radiosity)
        ASSERT_TRUE(std::isfinite(b));

    // Already cancelled: no iteration at all.
    request.onIteration = {};
    auto none = session.solve(request);
    ASSERT_TRUE(none.ok());
    EXPECT_TRUE(none->cancelled);
    EXPECT_EQ(none->iterations, 0);
}

// The F build tells an observer its progress (what the viewer draws): counts never decrease, and
// the last call is done == total, the number of unordered patch pairs.
TEST(Session, FormFactorBuildReportsProgress) {
    Session session = openOk(cornellSettings());
    std::mutex mutex;
    std::vector<std::pair<uint64_t, uint64_t>> calls;
    auto built =
        session.buildFormFactors(nullptr, [&](std::string_view, uint64_t done, uint64_t total) {
            std::lock_guard lock(mutex);
            calls.emplace_back(done, total);
        });
    ASSERT_TRUE(built.ok());
    ASSERT_FALSE(calls.empty());
    const uint64_t n = session.patches().patchCount();
    EXPECT_EQ(calls.back().first, calls.back().second);
    EXPECT_EQ(calls.back().second, n * (n - 1) / 2);
    EXPECT_EQ(calls.back().second, built->stats.pairs);
}

// A cancelled F build is an error that says so, and leaves no F.
TEST(Session, CancelledFormFactorBuildLeavesNoMatrix) {
    Session session = openOk(cornellSettings());
    CancelToken token;
    token.cancel();
    auto built = session.buildFormFactors(&token);
    ASSERT_FALSE(built.ok());
    EXPECT_NE(built.error().message.find("interrupted"), std::string::npos)
        << built.error().message;
    EXPECT_FALSE(session.hasFormFactors());
}

// The disk cache through the session: the second session reads F (bit for bit) instead of
// building it, also after a material and a wavelength-set change, which F does not depend on;
// a change of the rays per pair is another key.
TEST(Session, DiskCacheIsReusedAcrossMaterialAndWavelengthChanges) {
    const auto cache = test::testTempDir() / "cache";
    Session first = openOk(cornellSettings(cache));
    auto built = first.buildFormFactors();
    ASSERT_TRUE(built.ok());
    EXPECT_FALSE(built->fromCache);
    EXPECT_TRUE(built->cacheWarning.empty()) << built->cacheWarning;
    EXPECT_TRUE(first.formFactorsCached());

    SessionSettings other = cornellSettings(cache);
    other.wavelengths = *parseWavelengthSpec("visible");
    other.wavelengthsText = "visible";
    Session second = openOk(other);
    const std::size_t white = materialIndex(second, "white");
    Material edited = second.scene().materials[white];
    edited.baseColor = {0.3, 0.5, 0.3};
    edited.spectral.reflectance.reset();
    ASSERT_TRUE(second.setMaterial(white, edited).ok());
    auto read = second.buildFormFactors();
    ASSERT_TRUE(read.ok());
    EXPECT_TRUE(read->fromCache);
    EXPECT_EQ(second.formFactorBuildCount(), 0u);
    expectSameFactors(first.transport(), second.transport());
    EXPECT_EQ(read->stats.raysCast, built->stats.raysCast);
    ASSERT_TRUE(second.solve().ok());

    SessionSettings moreRays = cornellSettings(cache);
    moreRays.formFactors.raysPerPair = 8;
    Session third = openOk(moreRays);
    EXPECT_FALSE(third.formFactorsCached());
}

// The cache store runs in the background while the solve reads F: once it has
// finished, the entry on disk is F bit for bit, with the build's stats, and the solve that ran
// alongside it matches one from a session without a cache.
TEST(Session, BackgroundCacheStoreWritesTheMatrixSolvedWith) {
    const auto cache = test::testTempDir() / "cache";
    Session session = openOk(cornellSettings(cache));
    auto built = session.buildFormFactors();
    ASSERT_TRUE(built.ok());
    ASSERT_FALSE(built->fromCache);
    auto solved = session.solve();
    ASSERT_TRUE(solved.ok());
    EXPECT_EQ(session.finishCacheWrite(), "");
    EXPECT_EQ(session.finishCacheWrite(), "");  // nothing pending any more
    const CacheLookup lookup =
        FormFactorCache(cache).load(session.formFactorKey(), /*maxMemoryBytes=*/0);
    ASSERT_EQ(lookup.status, CacheLookup::Status::Hit) << lookup.message;
    expectSameFactors(MatrixTransport(lookup.matrix), session.transport());
    EXPECT_EQ(lookup.stats.raysCast, built->stats.raysCast);

    Session uncached = openOk(cornellSettings());
    auto reference = uncached.solve();
    ASSERT_TRUE(reference.ok());
    ASSERT_EQ(solved->radiosity.size(), reference->radiosity.size());
    for (std::size_t i = 0; i < solved->radiosity.size(); ++i)
        ASSERT_NEAR(solved->radiosity[i], reference->radiosity[i],
                    1e-12 * (1 + std::abs(reference->radiosity[i])))
            << "entry " << i;
}

// A store that fails in the background (the cache folder's parent is a file) is a warning that
// finishCacheWrite returns, not an error; F and the solve are unaffected.
TEST(Session, FailedBackgroundCacheStoreIsAWarning) {
    const auto dir = test::testTempDir();
    const std::string file = test::writeFile(dir, "file", "not a folder");
    Session session = openOk(cornellSettings(std::filesystem::path(file) / "cache"));
    auto built = session.buildFormFactors();
    ASSERT_TRUE(built.ok());
    EXPECT_TRUE(built->cacheWarning.empty()) << built->cacheWarning;
    ASSERT_TRUE(session.solve().ok());
    const std::string warning = session.finishCacheWrite();
    EXPECT_NE(warning.find("F not cached: cannot create the cache folder"), std::string::npos)
        << warning;
    EXPECT_FALSE(session.formFactorsCached());
}

// A wavelength edit keeps F and drops the solution (its size changes).
TEST(Session, WavelengthEditKeepsF) {
    Session session = openOk(cornellSettings());
    ASSERT_TRUE(session.solve().ok());
    ASSERT_TRUE(session.setWavelengths(*parseWavelengthSpec("meyer4"), "meyer4").ok());
    EXPECT_FALSE(session.hasSolution());
    EXPECT_EQ(session.system().wavelengthCount, 4u);
    ASSERT_TRUE(session.solve().ok());
    EXPECT_EQ(session.solution().radiosity.size(), session.patches().patchCount() * 4u);
    EXPECT_EQ(session.formFactorBuildCount(), 1u);
}

// A bad edit (a tabulated reflectance over 1) is refused with the material's name and leaves the
// session as it was.
TEST(Session, InvalidMaterialEditIsRefused) {
    Session session = openOk(cornellSettings());
    const std::size_t red = materialIndex(session, "red");
    const RadiositySystem before = session.system();
    Material bad = session.scene().materials[red];
    bad.spectral.reflectance = SpectrumSpec{TabulatedSpectrum{{400, 700}, {1.5, 1.5}}, 1.0};
    auto edited = session.setMaterial(red, bad);
    ASSERT_FALSE(edited.ok());
    EXPECT_NE(edited.error().message.find("red"), std::string::npos) << edited.error().message;
    EXPECT_EQ(session.system().operators.size(), before.operators.size());
    EXPECT_EQ(session.system().emission, before.emission);
    const auto& kept = session.scene().materials[red].spectral.reflectance;
    EXPECT_FALSE(kept && std::holds_alternative<TabulatedSpectrum>(kept->shape) &&
                 std::get<TabulatedSpectrum>(kept->shape).values[0] == 1.5);
}

// Making a wall fluorescent in a room lit by a black light: the `auto` set gains its UV samples
// (DESIGN.md section 4), the old-sized solution is dropped, F is kept, and the wall now glows.
TEST(Session, FluorescentEditAddsTheUvSamples) {
    Scene scene = verify::unitRoomScene(2, "blacklight");  // face f has material f
    SessionSettings settings;
    settings.backend = "cpu";
    settings.subdivideMaxEdge = 0;
    settings.formFactors.progress = false;
    settings.logStages = false;
    auto session = Session::fromScene(std::move(scene), settings);
    ASSERT_TRUE(session.ok()) << session.error().message;
    ASSERT_TRUE(session->solve().ok());
    const std::size_t before = session->wavelengths().size();
    EXPECT_GE(session->wavelengths().wavelengthNm(0), 400.0);  // no fluorescence: no UV samples

    Material glowing = session->scene().materials[0];
    glowing.spectral.fluorescence = FluorophorePreset{"fluorescein"};
    ASSERT_TRUE(session->setMaterial(0, glowing).ok());
    EXPECT_GT(session->wavelengths().size(), before);
    EXPECT_LT(session->wavelengths().wavelengthNm(0), 400.0);
    EXPECT_FALSE(session->hasSolution());
    EXPECT_EQ(session->fluorescentOperatorCount(), 1u);
    ASSERT_TRUE(session->solve().ok());
    EXPECT_EQ(session->formFactorBuildCount(), 1u);
    EXPECT_GT(meanY(*session, 0), 0.0);
}

// The display colours of the white furnace (tools/make_analytic_scenes.py: closed cube, flat
// reflectance 0.5, flat emission 1, so B = E / (1 - rho) = 2 and the radiance 2 / pi everywhere):
// every corner's linear sRGB is the sRGB of that flat radiance, to the row sums' accuracy.
TEST(Session, FurnaceCornerColoursAreTheExactRadiance) {
    SessionSettings settings;
    settings.scenePath = test::assetPath("scenes/furnace_box.gltf");
    settings.backend = "cpu";
    settings.subdivideMaxEdge = 0;
    settings.formFactors.progress = false;
    settings.solver.tolerance = 1e-6;
    settings.logStages = false;
    Session session = openOk(settings);
    ASSERT_TRUE(session.solve().ok());
    const std::vector<double> radiance(session.wavelengths().size(), 2.0 / std::numbers::pi);
    const Rgb expected = xyzToLinearSrgb(session.wavelengths().toXyz(radiance));
    const std::vector<float> rgb = session.cornerLinearSrgb();
    ASSERT_EQ(rgb.size(), std::size_t(session.patches().patchCount()) * 3 * 3);
    for (std::size_t k = 0; k < rgb.size(); ++k)
        ASSERT_NEAR(rgb[k], expected[k % 3], 0.02 * expected[k % 3]) << k;
    // Scaled by an exposure factor.
    EXPECT_NEAR(session.cornerLinearSrgb(0.5)[0], 0.5 * rgb[0], 1e-6 * rgb[0]);
}

}  // namespace
}  // namespace daisy
