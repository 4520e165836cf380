// `daisy cache list|clear|prune` and --cache-size through the command line (docs/cache.md,
// docs/cli.md): synthetic entries written with the cache-file layer keep the runs fast; one
// solve of two parallel plates stores a real F entry.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "core/cache_file.h"
#include "test_util.h"

namespace daisy {
namespace {

namespace fs = std::filesystem;
using test::runDaisy;
using test::RunResult;

// An entry of the layer with a 1,000-byte payload (1,064 bytes), last used `hoursAgo` hours ago.
void writeEntry(const fs::path& dir, const std::string& name, int hoursAgo) {
    CacheFileHeader header;
    header.magic = {'D', 'A', 'I', 'S', 'Y', 'T', 'S', 'T'};
    header.version = 1;
    const std::vector<std::byte> payload(1000, std::byte{1});
    const std::span<const std::byte> parts[] = {payload};
    fs::create_directories(dir);
    ASSERT_TRUE(writeCacheFile(dir / name, header, parts).ok());
    fs::last_write_time(dir / name,
                        fs::file_time_type::clock::now() - std::chrono::hours(hoursAgo));
}

using test::fileNames;

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

TEST(CacheCommandCli, ListPruneAndClear) {
    const fs::path dir = test::testTempDir() / "cache";
    writeEntry(dir, "old.dff", 3);
    writeEntry(dir, "mid.dff", 2);
    writeEntry(dir, "new.dff", 1);
    test::writeFile(dir, "notes.txt", "not the cache's");
    const std::string folder = " --cache " + dir.string();

    const RunResult list = runDaisy("cache list" + folder + " --cache-size 1M");
    ASSERT_EQ(list.status, 0) << list.output;
    EXPECT_TRUE(contains(list.output, "cache folder " + dir.string())) << list.output;
    // Most recently used first, with what each holds; the total and the limit.
    const std::size_t newAt = list.output.find("new.dff"), oldAt = list.output.find("old.dff");
    ASSERT_NE(newAt, std::string::npos) << list.output;
    ASSERT_NE(oldAt, std::string::npos) << list.output;
    EXPECT_LT(newAt, oldAt) << list.output;
    EXPECT_TRUE(contains(list.output, "DAISYTST entry, format version 1")) << list.output;
    EXPECT_TRUE(contains(list.output, "3 entries, 3.12 KiB; limit 1.00 MiB (--cache-size)"))
        << list.output;
    EXPECT_FALSE(contains(list.output, "notes.txt")) << list.output;

    // Two entries fit in 2,200 bytes: the least recently used goes.
    const RunResult prune = runDaisy("cache prune" + folder + " --cache-size 2200");
    ASSERT_EQ(prune.status, 0) << prune.output;
    EXPECT_TRUE(contains(prune.output, "evicted 1 entry (1.04 KiB); 2 entries left"))
        << prune.output;
    EXPECT_EQ(fileNames(dir), (std::vector<std::string>{"mid.dff", "new.dff", "notes.txt"}));

    const RunResult clear = runDaisy("cache clear" + folder);
    ASSERT_EQ(clear.status, 0) << clear.output;
    EXPECT_TRUE(contains(clear.output, "removed 2 entries")) << clear.output;
    EXPECT_EQ(fileNames(dir), std::vector<std::string>{"notes.txt"});

    const RunResult empty = runDaisy("cache list" + folder);
    ASSERT_EQ(empty.status, 0) << empty.output;
    EXPECT_TRUE(contains(empty.output, "0 entries, 0 B; limit ")) << empty.output;
    EXPECT_TRUE(contains(empty.output, "(the default")) << empty.output;
}

// Without --cache, the folder of the other commands: $XDG_CACHE_HOME/daisyriot (runDaisy sets
// XDG_CACHE_HOME to the test's own folder). A stale temporary (its writer's pid is gone) is
// removed by prune.
TEST(CacheCommandCli, FollowsXdgCacheHomeAndRemovesStaleTemporaries) {
    const fs::path dir = test::testCacheHome() / "daisyriot";
    writeEntry(dir, "entry.dff", 1);
    test::writeFile(dir, "entry.dff.tmp-999999999", "DAISYFF");  // above any pid_max
    const RunResult list = runDaisy("cache list");
    ASSERT_EQ(list.status, 0) << list.output;
    EXPECT_TRUE(contains(list.output, "entry.dff")) << list.output;
    EXPECT_TRUE(contains(list.output, "stale")) << list.output;
    const RunResult prune = runDaisy("cache prune");
    ASSERT_EQ(prune.status, 0) << prune.output;
    EXPECT_TRUE(contains(prune.output, "evicted 0 entries")) << prune.output;
    EXPECT_TRUE(contains(prune.output, "removed 1 temporary file of dead writers")) << prune.output;
    EXPECT_EQ(fileNames(dir), std::vector<std::string>{"entry.dff"});
}

// Real entries (F and B): listed with their kinds; an F larger than --cache-size is not stored, and
// the run says so in one line and succeeds.
TEST(CacheCommandCli, SolveHonoursTheLimit) {
    const std::string scene = test::assetPath("scenes/parallel_plates.gltf");
    const fs::path dir = test::testTempDir() / "cache";
    const std::string folder = " --cache " + dir.string();
    const RunResult tooSmall = runDaisy("solve " + scene + folder + " --cache-size 64");
    ASSERT_EQ(tooSmall.status, 0) << tooSmall.output;
    EXPECT_TRUE(contains(tooSmall.output, "is over the cache size limit of 64 B (--cache-size)"))
        << tooSmall.output;
    EXPECT_TRUE(!fs::exists(dir) || fileNames(dir).empty());

    const RunResult solve = runDaisy("solve " + scene + folder + " --cache-size 1G");
    ASSERT_EQ(solve.status, 0) << solve.output;
    // F and the converged solution, each listed with its kind.
    ASSERT_EQ(fileNames(dir).size(), 2u);
    const RunResult list = runDaisy("cache list" + folder);
    ASSERT_EQ(list.status, 0) << list.output;
    for (const std::string& name : fileNames(dir))
        EXPECT_TRUE(contains(list.output, name)) << list.output;
    EXPECT_TRUE(contains(list.output, "F: ")) << list.output;
    EXPECT_TRUE(contains(list.output, " patches, ")) << list.output;
    EXPECT_TRUE(contains(list.output, "B: ")) << list.output;
    EXPECT_TRUE(contains(list.output, " wavelengths (a converged solution)")) << list.output;
}

TEST(CacheCommandCli, BadUsage) {
    const RunResult action = runDaisy("cache tidy");
    EXPECT_EQ(action.status, 2) << action.output;
    const RunResult size = runDaisy("cache prune --cache-size lots");
    EXPECT_EQ(size.status, 2) << size.output;
    EXPECT_TRUE(contains(size.output, "'lots' is not a cache size")) << size.output;
    const RunResult file =
        runDaisy("cache list --cache " + test::writeFile(test::testTempDir(), "f", "x"));
    EXPECT_EQ(file.status, 2) << file.output;
    EXPECT_TRUE(contains(file.output, "not a folder")) << file.output;
}

}  // namespace
}  // namespace daisy
