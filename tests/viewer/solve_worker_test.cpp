// The viewer's background solver (viewer/solve_worker.h) against the session solving directly:
// edits re-solved in the background, cancelled by newer ones, must converge to what a fresh
// session with the same materials gives; a bounce step must be exactly one Jacobi step
// B = E + M F B from the reset B = E (the radiosity equation, DESIGN.md section 2).
#if DAISY_HAVE_VIEWER
#include "viewer/solve_worker.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <thread>

#include "pipeline/solution_cache.h"
#include "session_util.h"
#include "test_util.h"
#include "verify/scenes.h"

namespace daisy::viewer {
namespace {

constexpr double kPi = 3.14159265358979323846;

Scene room() {
    return verify::unitRoomScene(3, "D65");  // face f has material f
}

Session solvedRoom(const std::vector<std::pair<std::size_t, Material>>& edits = {}) {
    SessionSettings settings = test::unitRoomSettings();
    auto session = Session::fromScene(room(), settings);
    EXPECT_TRUE(session.ok()) << session.error().message;
    for (const auto& [index, material] : edits)
        EXPECT_TRUE(session->setMaterial(index, material).ok());
    EXPECT_TRUE(session->solve().ok());
    return std::move(*session);
}

Material withReflectance(Material material, std::array<double, 3> rgb) {
    material.spectral.reflectance = SpectrumSpec{RgbSpectrum{rgb}, 1.0};
    return material;
}

void waitIdle(const SolveWorker& worker) {
    for (int k = 0; k < 3000 && !worker.idle(); ++k)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ASSERT_TRUE(worker.idle()) << "the worker did not finish within 30 s";
}

// The snapshot shows what `direct` (a session solved directly) holds, to 1e-5 of the largest.
void expectSameChannels(const DisplaySnapshot& snapshot, const Session& direct) {
    const std::vector<float> expected = direct.patchChannels(true);
    ASSERT_EQ(snapshot.patchValues.size(), expected.size());
    double worst = 0, largest = 0;
    for (std::size_t k = 0; k < expected.size(); ++k) {
        worst = std::max(worst, double(std::abs(snapshot.patchValues[k] - expected[k])));
        largest = std::max(largest, double(std::abs(expected[k])));
    }
    EXPECT_LT(worst, 1e-5 * largest);
}

TEST(SolveWorker, EditsCancelledByNewerOnesConvergeToTheDirectSolve) {
    const Scene scene = room();
    const Material green = withReflectance(scene.materials[0], {0.1, 0.8, 0.1});
    const Material dark = withReflectance(scene.materials[2], {0.2, 0.2, 0.2});
    SolveWorker worker(solvedRoom());
    // Posted back to back: the first edit's solve is cancelled by the second edit.
    worker.setMaterial(0, withReflectance(scene.materials[0], {0.9, 0.1, 0.1}));
    worker.setMaterial(0, green);
    worker.setMaterial(2, dark);
    waitIdle(worker);
    const auto snapshot = worker.latest();
    EXPECT_FALSE(snapshot->solving);
    EXPECT_TRUE(snapshot->converged);
    EXPECT_EQ(snapshot->refusedEdits, 0);

    const Session direct = solvedRoom({{0, green}, {2, dark}});
    expectSameChannels(*snapshot, direct);
}

// With the hierarchical transport, an edit that makes another wall a lamp is solved on the
// links in hand, then the links are refined again in the background: the worker ends on the
// links a fresh session with the edit builds, and shows its solution.
TEST(SolveWorker, AnEditThatMovesLightRefinesTheLinksInTheBackground) {
    SessionSettings settings = test::unitRoomSettings();
    settings.transport = TransportKind::Hierarchical;
    const Scene scene = verify::unitRoomScene(8, "D65");  // all pairs near links at 3
    const auto open = [&](const std::vector<std::pair<std::size_t, Material>>& edits) {
        auto session = Session::fromScene(scene, settings);
        EXPECT_TRUE(session.ok()) << session.error().message;
        for (const auto& [index, material] : edits)
            EXPECT_TRUE(session->setMaterial(index, material).ok());
        EXPECT_TRUE(session->solve().ok());
        return std::move(*session);
    };
    Material lamp = scene.materials[4];
    lamp.spectral.emission = scene.materials[1].spectral.emission;
    SolveWorker worker(open({}));
    waitIdle(worker);
    const TransportStats before = worker.transportStats();
    worker.setMaterial(4, lamp);
    waitIdle(worker);
    const auto snapshot = worker.latest();
    EXPECT_TRUE(snapshot->converged);
    EXPECT_EQ(snapshot->message, "");

    const Session direct = open({{4, lamp}});
    EXPECT_EQ(worker.transportStats().entries, direct.transport().stats().entries);
    EXPECT_NE(worker.transportStats().entries, before.entries);
    expectSameChannels(*snapshot, direct);
}

TEST(SolveWorker, OneBounceFromEmissionIsOneJacobiStep) {
    Session session = solvedRoom();
    const RadiositySystem system = session.system();
    const std::shared_ptr<const Transport> transport = session.sharedTransport();
    SolveWorker worker(std::move(session));
    worker.resetToEmission();
    waitIdle(worker);
    worker.stepBounce();
    waitIdle(worker);
    const auto snapshot = worker.latest();
    EXPECT_EQ(snapshot->iteration, 1);
    const std::size_t n = system.patchCount, m = system.wavelengthCount;
    std::vector<TransportEntry> row;
    double worst = 0, largest = 0;
    for (uint32_t i = 0; i < n; ++i) {
        const MaterialOperator& op = system.operators[system.patchOperator[i]];
        transport->row(i, row);
        for (std::size_t k = 0; k < m; ++k) {
            double gathered = 0;
            for (const TransportEntry& entry : row)
                gathered += entry.factor * system.emission[entry.patch * m + k];
            const double b = system.emission[i * m + k] + op.diagonal[k] * gathered;
            // patchValues: radiance L = B / pi per sample (channel_layout.h).
            const double shown = kPi *
                snapshot->patchValues[i * std::size_t(snapshot->layout.count()) +
                                      std::size_t(snapshot->layout.radiance(k))];
            worst = std::max(worst, std::abs(shown - b));
            largest = std::max(largest, b);
        }
    }
    EXPECT_GT(largest, 0);
    EXPECT_LT(worst, 1e-5 * largest);
}

TEST(SolveWorker, RefusedEditKeepsTheMaterialAndSaysWhy) {
    const Scene scene = room();
    SolveWorker worker(solvedRoom());
    Material bad = scene.materials[3];
    bad.spectral.reflectance = SpectrumSpec{TabulatedSpectrum{{400, 700}, {1.5, 1.5}}, 1.0};
    worker.setMaterial(3, bad);
    waitIdle(worker);
    const auto snapshot = worker.latest();
    EXPECT_EQ(snapshot->refusedEdits, 1);
    EXPECT_NE(snapshot->message.find("edit refused"), std::string::npos) << snapshot->message;
    EXPECT_NE(snapshot->message.find("face3"), std::string::npos) << snapshot->message;
    EXPECT_FALSE(snapshot->materials[3].spectral.reflectance.has_value());
}

// The smallest patch radiance of material `material` in `snapshot` (visible samples only).
double darkestPatch(const DisplaySnapshot& snapshot, const PatchMesh& patches,
                    std::size_t material) {
    double darkest = 1e300;
    const std::size_t stride = std::size_t(snapshot.layout.count());
    for (std::size_t p = 0; p < patches.patchCount(); ++p) {
        if (patches.materials[p] != material) continue;
        double sum = 0;
        for (std::size_t k = 0; k < snapshot.wavelengthCount; ++k) {
            if (snapshot.wavelengthsNm[k] < 400 || snapshot.wavelengthsNm[k] > 700) continue;
            sum += snapshot.patchValues[p * stride + std::size_t(snapshot.layout.radiance(k))];
        }
        darkest = std::min(darkest, sum);
    }
    return darkest;
}

// A slider drag posts an edit per frame, each cancelling the solve of the one before, often
// before its first sweep. No snapshot on the way may show the dragged material black: its
// preview bounces the light of the last finished solve, never a cancelled solve's zeros.
TEST(SolveWorker, ADragOfManyEditsNeverShowsTheEditedMaterialBlack) {
    const Scene scene = room();
    SolveWorker worker(solvedRoom());
    const double before = darkestPatch(*worker.latest(), worker.patches(), 0);
    ASSERT_GT(before, 0);
    double darkest = 1e300;
    uint64_t seen = 0;
    const auto look = [&] {
        const auto snapshot = worker.latest();
        if (snapshot->version == seen) return;
        seen = snapshot->version;
        worker.shown(seen);
        darkest = std::min(darkest, darkestPatch(*snapshot, worker.patches(), 0));
    };
    for (int step = 0; step < 40; ++step) {
        const double grey = 0.5 + 0.01 * step;
        worker.setMaterial(0, withReflectance(scene.materials[0], {grey, grey, grey}));
        for (int k = 0; k < 4; ++k) {
            look();
            std::this_thread::sleep_for(std::chrono::microseconds(500));
        }
    }
    for (int k = 0; k < 3000 && !worker.idle(); ++k) {
        look();
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    look();
    ASSERT_TRUE(worker.idle());
    EXPECT_TRUE(worker.latest()->converged);
    // Reflectance 0.5 to 0.89 against the start's (the base material's): never below a third.
    EXPECT_GT(darkest, before / 3)
        << "a snapshot showed the edited material at " << darkest << " of " << before;
}

// A refused edit right after an accepted one cancels that edit's solve; the worker must finish
// it (converged, the accepted edit's solution), keep the refused material out and say why.
TEST(SolveWorker, ARefusedEditStillLetsTheAcceptedEditConverge) {
    const Scene scene = room();
    const Material green = withReflectance(scene.materials[0], {0.1, 0.8, 0.1});
    Material bad = scene.materials[3];
    bad.spectral.reflectance = SpectrumSpec{TabulatedSpectrum{{400, 700}, {1.5, 1.5}}, 1.0};
    SolveWorker worker(solvedRoom());
    worker.setMaterial(0, green);
    worker.setMaterial(3, bad);
    waitIdle(worker);
    const auto snapshot = worker.latest();
    EXPECT_EQ(snapshot->refusedEdits, 1);
    EXPECT_EQ(snapshot->refusedMaterial, 3u);
    EXPECT_NE(snapshot->message.find("edit refused"), std::string::npos) << snapshot->message;
    EXPECT_TRUE(snapshot->converged);
    EXPECT_FALSE(snapshot->solving);
    const Session direct = solvedRoom({{0, green}});
    expectSameChannels(*snapshot, direct);
}

// The window opens before F exists: the worker's first snapshot is B = E (building), then it
// makes F on its thread and converges to what the session solving directly gives.
TEST(SolveWorker, ShowsTheEmissionWhileFIsMadeThenConverges) {
    SessionSettings settings = test::unitRoomSettings();
    auto session = Session::fromScene(room(), settings);
    ASSERT_TRUE(session.ok()) << session.error().message;
    const std::vector<double> emission = session->system().emission;
    // F waits for the first frame, so the build cannot have ended when the test looks.
    SolveWorker worker(std::move(*session), /*waitForFirstFrame=*/true);
    const auto first = worker.latest();
    EXPECT_TRUE(first->building);
    ASSERT_EQ(first->radiosity.size(), emission.size());
    if (first->version == 1) {
        EXPECT_EQ(first->radiosity, emission);  // the constructor's picture: B = E
    } else {
        // The worker's thread already showed the direct light, E + M H: never less than E.
        for (std::size_t k = 0; k < emission.size(); ++k)
            EXPECT_GE(first->radiosity[k], emission[k]) << k;
    }
    worker.shown(first->version);
    waitIdle(worker);
    const auto last = worker.latest();
    EXPECT_FALSE(last->building);
    EXPECT_TRUE(last->converged);
    EXPECT_STREQ(worker.transportKind(), "matrix");
    EXPECT_GT(worker.transportStats().entries, 0u);
    EXPECT_FALSE(worker.buildProgress().active);
    const std::vector<float> expected = solvedRoom().patchChannels(true);
    ASSERT_EQ(last->patchValues.size(), expected.size());
    double worst = 0, largest = 0;
    for (std::size_t k = 0; k < expected.size(); ++k) {
        worst = std::max(worst, double(std::abs(last->patchValues[k] - expected[k])));
        largest = std::max(largest, double(std::abs(expected[k])));
    }
    EXPECT_LT(worst, 1e-5 * largest);
}

// Closing the window while F is being made cancels the build (core/cancel.h): the worker's
// destructor returns within a second, long before the build would have ended.
TEST(SolveWorker, ClosingWhileFIsMadeCancelsTheBuild) {
    SessionSettings settings = test::unitRoomSettings();
    // 6 faces x 24^2 x 2 = 6,912 patches: F takes several seconds on any machine.
    auto session = Session::fromScene(verify::unitRoomScene(24, "D65"), settings);
    ASSERT_TRUE(session.ok()) << session.error().message;
    auto worker = std::make_unique<SolveWorker>(std::move(*session));
    // The pair loop has reported progress (the build is under way, its ETA known or not).
    BuildProgress progress;
    for (int k = 0; k < 6000; ++k) {
        progress = worker->buildProgress();
        if (progress.stage == "view factors" && progress.fraction > 0) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_TRUE(progress.active);
    ASSERT_EQ(progress.stage, "view factors");
    EXPECT_LT(progress.fraction, 1.0);
    EXPECT_TRUE(worker->latest()->building);
    EXPECT_STREQ(worker->transportKind(), "");
    const auto start = std::chrono::steady_clock::now();
    worker.reset();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(seconds, 1.0);
}

// A warm open: the converged solution the disk cache holds for these materials is shown as it
// was stored, and nothing is solved (the worker's iteration count is the stored solve's).
TEST(SolveWorker, AWarmOpenShowsTheCachedSolutionWithoutSolving) {
    SessionSettings settings = test::unitRoomSettings();
    settings.cacheDirectory = test::testTempDir() / "cache";
    auto cold = Session::fromScene(room(), settings);
    ASSERT_TRUE(cold.ok());
    SolveWorker coldWorker(std::move(*cold));
    waitIdle(coldWorker);
    const auto solved = coldWorker.latest();
    ASSERT_TRUE(solved->converged);
    EXPECT_FALSE(solved->fromCache);

    auto warm = Session::fromScene(room(), settings);
    ASSERT_TRUE(warm.ok());
    // The cold session's background store of B has landed.
    const auto entry = SolutionCache(*settings.cacheDirectory).entryPath(warm->solutionKey());
    for (int k = 0; k < 200 && !std::filesystem::exists(entry); ++k)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    SolveWorker warmWorker(std::move(*warm));
    waitIdle(warmWorker);
    const auto shown = warmWorker.latest();
    EXPECT_TRUE(shown->fromCache);
    EXPECT_TRUE(shown->converged);
    EXPECT_EQ(shown->iteration, solved->iteration);
    EXPECT_EQ(shown->radiosity, solved->radiosity);
    EXPECT_EQ(shown->gathered, solved->gathered);
    EXPECT_STREQ(warmWorker.transportKind(), "matrix");
}

}  // namespace
}  // namespace daisy::viewer
#endif
