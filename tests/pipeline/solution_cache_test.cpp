// The disk cache of converged solutions (pipeline/solution_cache.h) through the session: a
// converged B stored by one session is adopted by the next with the same F key, materials,
// wavelengths and solver settings, bit for bit and without a solve; any of those changed is a
// miss; a damaged entry is rejected in one line and solved again.
#include "pipeline/solution_cache.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <utility>
#include <vector>

#include "pipeline/session.h"
#include "session_util.h"
#include "test_util.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

// The unit room, 6 x 3 x 3 x 2 = 108 patches, the ceiling emitting D65, face 0 the material
// edited below; the cpu backend and a cache in `cache`.
SessionSettings roomSettings(const std::filesystem::path& cache) {
    SessionSettings settings = test::unitRoomSettings();
    settings.cacheDirectory = cache;
    return settings;
}

Session openRoom(const SessionSettings& settings) {
    auto session = Session::fromScene(verify::unitRoomScene(3, "D65"), settings);
    EXPECT_TRUE(session.ok()) << session.error().message;
    return std::move(*session);
}

SolveRequest cachedSolve() {
    SolveRequest request;
    request.useSolutionCache = true;
    return request;
}

std::vector<std::filesystem::path> solutionEntries(const std::filesystem::path& dir) {
    std::vector<std::filesystem::path> found;
    if (!std::filesystem::exists(dir)) return found;
    for (const auto& entry : std::filesystem::directory_iterator(dir))
        if (entry.path().extension() == ".dbr") found.push_back(entry.path());
    return found;
}

// The first session solves and stores B; the second adopts it before F exists (the viewer's warm
// open) and its solve request is answered from the cache too: the same bits, no iterations run.
TEST(SolutionCache, ARoundTripGivesTheSolvedBitsWithoutASolve) {
    const auto cache = test::testTempDir() / "cache";
    Session first = openRoom(roomSettings(cache));
    auto solved = first.solve(cachedSolve());
    ASSERT_TRUE(solved.ok()) << solved.error().message;
    ASSERT_TRUE(solved->converged);
    EXPECT_FALSE(solved->changeHistory.empty());  // a real solve
    EXPECT_EQ(first.finishCacheWrite(), "");
    ASSERT_EQ(solutionEntries(cache).size(), 1u);
    EXPECT_EQ(solutionEntries(cache)[0], SolutionCache(cache).entryPath(first.solutionKey()));

    Session second = openRoom(roomSettings(cache));
    EXPECT_EQ(second.solutionKey(), first.solutionKey());
    const SolutionCacheReport report = second.loadCachedSolution();
    ASSERT_TRUE(report.hit) << report.warning;
    EXPECT_FALSE(second.hasFormFactors());
    ASSERT_TRUE(second.hasSolution());
    EXPECT_EQ(second.solution().radiosity, solved->radiosity);
    EXPECT_EQ(second.lastGathered(), first.lastGathered());
    EXPECT_EQ(second.solution().iterations, solved->iterations);
    EXPECT_EQ(second.solution().residual, solved->residual);
    EXPECT_TRUE(second.solution().converged);

    Session third = openRoom(roomSettings(cache));
    auto again = third.solve(cachedSolve());
    ASSERT_TRUE(again.ok()) << again.error().message;
    EXPECT_TRUE(again->changeHistory.empty()) << "solved instead of read";
    EXPECT_EQ(again->radiosity, solved->radiosity);
    // Its G is the one the first edit's preview bounces (Session::previewBounce).
    std::vector<uint8_t> all(third.patches().patchCount(), 1);
    EXPECT_TRUE(third.previewBounce(all));
}

// The key follows what B depends on: an edited material, another wavelength set or another
// tolerance misses; the edit undone hits again.
TEST(SolutionCache, AnEditedMaterialMisses) {
    const auto cache = test::testTempDir() / "cache";
    Session first = openRoom(roomSettings(cache));
    ASSERT_TRUE(first.solve(cachedSolve()).ok());
    first.finishCacheWrite();

    Session edited = openRoom(roomSettings(cache));
    const Material original = edited.scene().materials[0];
    Material green = original;
    green.spectral.reflectance = SpectrumSpec{RgbSpectrum{{0.1, 0.8, 0.1}}, 1.0};
    ASSERT_TRUE(edited.setMaterial(0, green).ok());
    EXPECT_NE(edited.solutionKey(), first.solutionKey());
    EXPECT_FALSE(edited.loadCachedSolution().hit);
    EXPECT_FALSE(edited.hasSolution());
    ASSERT_TRUE(edited.setMaterial(0, original).ok());
    EXPECT_EQ(edited.solutionKey(), first.solutionKey());
    EXPECT_TRUE(edited.loadCachedSolution().hit);

    SessionSettings visible = roomSettings(cache);
    visible.wavelengths.preset = "meyer4";
    EXPECT_FALSE(openRoom(visible).loadCachedSolution().hit);
    SessionSettings tighter = roomSettings(cache);
    tighter.solver.tolerance = 1e-9;
    EXPECT_FALSE(openRoom(tighter).loadCachedSolution().hit);
}

// A flipped byte in B fails the payload checksum: one line naming the file, the file removed,
// and the solve runs (and stores B again).
TEST(SolutionCache, ADamagedEntryIsRejectedAndSolvedAgain) {
    const auto cache = test::testTempDir() / "cache";
    Session first = openRoom(roomSettings(cache));
    auto solved = first.solve(cachedSolve());
    ASSERT_TRUE(solved.ok());
    first.finishCacheWrite();
    const auto entry = SolutionCache(cache).entryPath(first.solutionKey());
    {
        std::fstream file(entry, std::ios::in | std::ios::out | std::ios::binary);
        char byte = 0;
        file.seekg(200);
        file.read(&byte, 1);
        byte = char(~byte);
        file.seekp(200);
        file.write(&byte, 1);
    }
    Session second = openRoom(roomSettings(cache));
    const SolutionCacheReport report = second.loadCachedSolution();
    EXPECT_FALSE(report.hit);
    EXPECT_NE(report.warning.find(entry.string() + ": payload checksum mismatch"),
              std::string::npos)
        << report.warning;
    EXPECT_FALSE(std::filesystem::exists(entry));
    auto again = second.solve(cachedSolve());
    ASSERT_TRUE(again.ok());
    EXPECT_FALSE(again->changeHistory.empty());
    EXPECT_EQ(again->radiosity, solved->radiosity);  // the solve is deterministic
    second.finishCacheWrite();
    EXPECT_TRUE(std::filesystem::exists(entry));
}

// A bounded solve (the viewer's bounce) and a cancelled one are not stored, nor looked up.
TEST(SolutionCache, BoundedAndUnconvergedSolvesAreNotStored) {
    const auto cache = test::testTempDir() / "cache";
    Session session = openRoom(roomSettings(cache));
    SolveRequest bounce = cachedSolve();
    bounce.maxIterations = 1;
    bounce.kind = SolverKind::Jacobi;
    ASSERT_TRUE(session.solve(bounce).ok());
    SessionSettings capped = roomSettings(cache);
    capped.solver.maxIterations = 2;
    Session cappedSession = openRoom(capped);
    auto unconverged = cappedSession.solve(cachedSolve());
    ASSERT_TRUE(unconverged.ok());
    EXPECT_FALSE(unconverged->converged);
    session.finishCacheWrite();
    cappedSession.finishCacheWrite();
    EXPECT_TRUE(solutionEntries(cache).empty());
}

}  // namespace
}  // namespace daisy
