// The disk cache of F through the command line (docs/cache.md, docs/cli.md): a second render of
// the same geometry with another material, image size and wavelength set reads F instead of
// building it; `info` says so; a corrupted entry is reported in one line and rebuilt; --no-cache
// neither reads nor writes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "test_util.h"

namespace daisy {
namespace {

using test::runDaisy;
using test::RunResult;

const std::string kCornellBox = test::assetPath("scenes/cornell_box.gltf");

// The files of `dir`, or those with extension `extension` (".dff": F, ".dbr": solutions).
std::vector<std::filesystem::path> entries(const std::filesystem::path& dir,
                                           const std::string& extension = "") {
    std::vector<std::filesystem::path> found;
    if (!std::filesystem::is_directory(dir)) return found;
    for (const auto& entry : std::filesystem::directory_iterator(dir))
        if (extension.empty() || entry.path().extension() == extension)
            found.push_back(entry.path());
    return found;
}

TEST(CacheCli, SecondRenderReadsFAndCorruptionIsRebuilt) {
    const auto dir = test::testTempDir();
    const auto cache = dir / "cache";
    const std::string common = " --subdivide 0.15 --cache " + cache.string();
    const RunResult first =
        runDaisy("render " + kCornellBox + common + " --width 64 -o " + (dir / "a.png").string());
    ASSERT_EQ(first.status, 0) << first.output;
    EXPECT_EQ(first.output.find("from the cache"), std::string::npos) << first.output;
    // F, and the converged solution beside it (docs/cache.md, "Solutions (B)").
    ASSERT_EQ(entries(cache).size(), 2u);
    EXPECT_EQ(entries(cache, ".dff").size(), 1u);
    EXPECT_EQ(entries(cache, ".dbr").size(), 1u);

    const RunResult info = runDaisy("info " + kCornellBox + common);
    EXPECT_EQ(info.status, 0) << info.output;
    EXPECT_NE(info.output.find("cached F       yes"), std::string::npos) << info.output;

    // Another material (by --materials), image size and wavelength set: the same F.
    const std::string materials =
        test::writeFile(dir, "m.json", R"({"white": {"reflectance": {"rgb": [0.2, 0.6, 0.2]}}})");
    const RunResult second =
        runDaisy("render " + kCornellBox + common + " --materials " + materials +
                 " --wavelengths visible --width 48 -o " + (dir / "b.png").string());
    ASSERT_EQ(second.status, 0) << second.output;
    EXPECT_NE(second.output.find("from the cache"), std::string::npos) << second.output;
    EXPECT_EQ(entries(cache, ".dff").size(), 1u);
    // Other materials and wavelengths: another solution, solved and stored.
    EXPECT_EQ(second.output.find("solution from the cache"), std::string::npos) << second.output;
    EXPECT_EQ(entries(cache, ".dbr").size(), 2u);

    // Another K is another key: built and stored beside the first.
    const RunResult moreRays = runDaisy("render " + kCornellBox + common +
                                        " --rays 8 --width 32 -o " + (dir / "c.png").string());
    ASSERT_EQ(moreRays.status, 0) << moreRays.output;
    EXPECT_EQ(moreRays.output.find("from the cache"), std::string::npos) << moreRays.output;
    EXPECT_EQ(entries(cache, ".dff").size(), 2u);

    // Flip one byte in the middle of every entry: reported, rebuilt, stored again.
    for (const auto& path : entries(cache)) {
        std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
        file.seekg(0, std::ios::end);
        const auto size = static_cast<std::streamoff>(file.tellg());
        file.seekg(size / 2);
        char byte = 0;
        file.read(&byte, 1);
        byte = static_cast<char>(byte ^ 0x5a);
        file.seekp(size / 2);
        file.write(&byte, 1);
    }
    const RunResult corrupt =
        runDaisy("render " + kCornellBox + common + " --width 32 -o " + (dir / "d.png").string());
    ASSERT_EQ(corrupt.status, 0) << corrupt.output;
    EXPECT_NE(corrupt.output.find("checksum mismatch"), std::string::npos) << corrupt.output;
    EXPECT_NE(corrupt.output.find("rebuilding"), std::string::npos) << corrupt.output;
    EXPECT_EQ(corrupt.output.find("from the cache"), std::string::npos) << corrupt.output;
    const RunResult again =
        runDaisy("render " + kCornellBox + common + " --width 32 -o " + (dir / "e.png").string());
    ASSERT_EQ(again.status, 0) << again.output;
    EXPECT_NE(again.output.find("non-zeros from the cache"), std::string::npos) << again.output;
    // A warm render skips the solve: B (stored by the run before) comes from the cache too.
    EXPECT_NE(again.output.find("solve: the converged solution from the cache"), std::string::npos)
        << again.output;
}

TEST(CacheCli, NoCacheNeitherReadsNorWrites) {
    const auto dir = test::testTempDir();
    const RunResult run =
        runDaisy("formfactors " + kCornellBox + " --no-cache -o " + (dir / "F.mtx").string());
    ASSERT_EQ(run.status, 0) << run.output;
    // The default folder is the test's own XDG_CACHE_HOME (test_util.h): nothing was written.
    EXPECT_TRUE(entries(test::testCacheHome() / "daisyriot").empty());
    const RunResult info = runDaisy("info " + kCornellBox + " --no-cache");
    EXPECT_NE(info.output.find("cached F       no (--no-cache)"), std::string::npos) << info.output;
    const RunResult both = runDaisy("info " + kCornellBox + " --no-cache --cache " + dir.string());
    EXPECT_EQ(both.status, 2) << both.output;
}

// An explicit --backend that cannot run here fails even when the cache holds F from another
// backend of its family: `--backend cuda` must not answer with the reference backend's F.
TEST(CacheCli, ABackendThatCannotRunHereIsRefusedEvenOnACacheHit) {
    const auto dir = test::testTempDir();
    const std::string scene = kCornellBox + " --subdivide 0.2 --cache " + (dir / "cache").string() +
        " -o " + (dir / "F.mtx").string();
    const RunResult reference = runDaisy("formfactors " + scene + " --backend reference");
    ASSERT_EQ(reference.status, 0) << reference.output;
    ASSERT_EQ(entries(dir / "cache").size(), 1u);
    const RunResult uncached =
        runDaisy("formfactors " + kCornellBox + " --subdivide 0.2 --no-cache --backend cuda -o " +
                 (dir / "G.mtx").string());
    if (uncached.status == 0) GTEST_SKIP() << "the cuda backend runs here: " << uncached.output;
    const RunResult cuda = runDaisy("formfactors " + scene + " --backend cuda");
    EXPECT_EQ(cuda.status, 2) << cuda.output;
    EXPECT_NE(cuda.output.find("error: --backend cuda: "), std::string::npos) << cuda.output;
    EXPECT_EQ(cuda.output.find("from the cache"), std::string::npos) << cuda.output;
}

// A cache folder that cannot be created (its parent is a file) is a warning, not a failure.
TEST(CacheCli, UnwritableCacheFolderIsAWarning) {
    const auto dir = test::testTempDir();
    const std::string file = test::writeFile(dir, "file", "not a folder");
    const RunResult run = runDaisy("formfactors " + kCornellBox + " --cache " + file +
                                   "/cache -o " + (dir / "F.mtx").string());
    EXPECT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("F not cached"), std::string::npos) << run.output;
    EXPECT_TRUE(std::filesystem::exists(dir / "F.mtx"));
}

}  // namespace
}  // namespace daisy
