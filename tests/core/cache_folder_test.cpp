// A cache folder as a whole (core/cache_folder.h): least-recently-used eviction under a size
// limit, the entry just written kept, temporaries of dead writers removed while a running
// writer's is kept, and files that are not the cache's never touched.
#include "core/cache_folder.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "test_util.h"

namespace daisy {
namespace {

namespace fs = std::filesystem;

constexpr int64_t kSecondNs = 1'000'000'000;
constexpr int64_t kBaseNs = int64_t{1'700'000'000} * kSecondNs;  // November 2023

// Writes an entry of the layer with a payload of `payloadBytes` and sets its last use.
fs::path writeEntry(const fs::path& dir, const std::string& name, std::size_t payloadBytes,
                    int64_t lastUseNs) {
    CacheFileHeader header;
    header.magic = {'D', 'A', 'I', 'S', 'Y', 'T', 'S', 'T'};
    header.version = 1;
    const std::vector<std::byte> payload(payloadBytes, std::byte{7});
    const std::span<const std::byte> parts[] = {payload};
    const fs::path path = dir / name;
    EXPECT_TRUE(writeCacheFile(path, header, parts).ok());
    const timespec times[2] = {{lastUseNs / kSecondNs, lastUseNs % kSecondNs},
                               {lastUseNs / kSecondNs, lastUseNs % kSecondNs}};
    EXPECT_EQ(utimensat(AT_FDCWD, path.c_str(), times, 0), 0);
    return path;
}

using test::fileNames;

// The pid of a child that has exited and been reaped: no process has it (until the kernel
// hands it out again, which takes a wrap of the pid space).
// Four entries of 1,064 bytes, used in the order b, d, a, c (c most recently).
class CacheFolder : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = test::testTempDir();
        writeEntry(dir_, "a.dff", 1000, kBaseNs + 3 * kSecondNs);
        writeEntry(dir_, "b.dff", 1000, kBaseNs + 1 * kSecondNs);
        writeEntry(dir_, "c.dff", 1000, kBaseNs + 4 * kSecondNs);
        writeEntry(dir_, "d.dff", 1000, kBaseNs + 2 * kSecondNs);
    }
    fs::path dir_;
};

TEST_F(CacheFolder, ListsEntriesMostRecentlyUsedFirst) {
    test::writeFile(dir_, "notes.txt", "not a cache entry");
    const CacheFolderListing listing = listCacheFolder(dir_);
    ASSERT_EQ(listing.entries.size(), 4u);
    EXPECT_EQ(listing.entries[0].path.filename(), "c.dff");
    EXPECT_EQ(listing.entries[3].path.filename(), "b.dff");
    EXPECT_EQ(listing.entries[0].bytes, 1064u);
    EXPECT_EQ(listing.entries[0].lastUseNs, kBaseNs + 4 * kSecondNs);
    EXPECT_TRUE(listing.entries[0].headerValid);
    EXPECT_EQ(listing.entryBytes, 4 * 1064u);
    EXPECT_TRUE(listing.temporaries.empty());
}

TEST_F(CacheFolder, EvictsLeastRecentlyUsedUntilUnderTheLimit) {
    // A use of b (the oldest) makes it the newest: d then a go first.
    markCacheEntryUsed(dir_ / "b.dff");
    const CachePruneReport report = pruneCacheFolder(dir_, 2 * 1064 + 500);
    EXPECT_EQ(report.evicted, 2);
    EXPECT_EQ(report.evictedBytes, 2 * 1064u);
    EXPECT_EQ(report.entriesLeft, 2);
    EXPECT_EQ(report.bytesLeft, 2 * 1064u);
    EXPECT_TRUE(report.failures.empty());
    EXPECT_EQ(fileNames(dir_), (std::vector<std::string>{"b.dff", "c.dff"}));
    // Under the limit already: nothing more goes.
    EXPECT_EQ(pruneCacheFolder(dir_, 2 * 1064).evicted, 0);
    EXPECT_EQ(pruneCacheFolder(dir_, 2 * 1064 - 1).evicted, 1);
    EXPECT_EQ(fileNames(dir_), std::vector<std::string>{"b.dff"});
}

TEST_F(CacheFolder, KeepsTheEntryJustWritten) {
    // b is the oldest but was just written: the others go, b stays though alone over the limit.
    const CachePruneReport report = pruneCacheFolder(dir_, 1000, dir_ / "b.dff");
    EXPECT_EQ(report.evicted, 3);
    EXPECT_EQ(fileNames(dir_), std::vector<std::string>{"b.dff"});
    EXPECT_EQ(report.bytesLeft, 1064u);
}

TEST_F(CacheFolder, MarkingAUseSetsTheModificationTimeToNow) {
    const auto before = fs::last_write_time(dir_ / "a.dff");
    markCacheEntryUsed(dir_ / "a.dff");
    EXPECT_GT(fs::last_write_time(dir_ / "a.dff"), before);
    EXPECT_EQ(listCacheFolder(dir_).entries[0].path.filename(), "a.dff");
}

TEST_F(CacheFolder, RemovesTemporariesOfDeadWritersOnly) {
    const std::string start(8, '\0');
    const std::string dead = "e.dff.tmp-" + std::to_string(test::deadPid());
    const std::string live = "f.dff.tmp-" + std::to_string(getpid());
    const std::string oldLive = "g.dff.tmp-" + std::to_string(getpid());
    test::writeFile(dir_, dead, "DAISYFF" + start);
    test::writeFile(dir_, live, "DAISYFF" + start);
    test::writeFile(dir_, oldLive, "");  // a writer killed before its first flush
    fs::last_write_time(dir_ / oldLive, fs::last_write_time(dir_ / live) - std::chrono::hours(25));
    test::writeFile(dir_, "notes.tmp-1", "somebody else's file");  // not one of ours: kept

    const CacheFolderListing listing = listCacheFolder(dir_);
    ASSERT_EQ(listing.temporaries.size(), 3u);
    EXPECT_EQ(listing.entries.size(), 4u);  // temporaries are not entries

    const CachePruneReport report = pruneCacheFolder(dir_, 1 << 20);
    EXPECT_EQ(report.temporariesRemoved, 2);
    EXPECT_EQ(report.liveTemporaries, 1);
    EXPECT_EQ(report.evicted, 0);
    EXPECT_TRUE(fs::exists(dir_ / live));
    EXPECT_FALSE(fs::exists(dir_ / dead));
    EXPECT_FALSE(fs::exists(dir_ / oldLive));
    EXPECT_TRUE(fs::exists(dir_ / "notes.tmp-1"));
}

TEST_F(CacheFolder, ClearRemovesEntriesAndNothingElse) {
    test::writeFile(dir_, "notes.txt", "DAIS");  // too short to be an entry
    test::writeFile(dir_, "other.bin", "NOTDAISY and longer than a magic");
    const std::string live = "f.dff.tmp-" + std::to_string(getpid());
    test::writeFile(dir_, live, "DAISYFF");
    const CachePruneReport report = clearCacheFolder(dir_);
    EXPECT_EQ(report.evicted, 4);
    EXPECT_EQ(report.entriesLeft, 0);
    EXPECT_EQ(report.liveTemporaries, 1);
    EXPECT_EQ(fileNames(dir_), (std::vector<std::string>{live, "notes.txt", "other.bin"}));
}

TEST(CacheFolderNames, TemporaryWriterPid) {
    EXPECT_EQ(temporaryWriterPid("0123.dff.tmp-4567"), 4567);
    EXPECT_EQ(temporaryWriterPid("x.tmp-"), -1);
    EXPECT_EQ(temporaryWriterPid("x.tmp-12a"), -1);
    EXPECT_EQ(temporaryWriterPid("x.dff"), -1);
    EXPECT_EQ(temporaryWriterPid(".tmp-12"), -1);
    EXPECT_TRUE(processIsAlive(getpid()));
    EXPECT_FALSE(processIsAlive(test::deadPid()));
}

TEST(CacheFolderLimit, DefaultIsAtMostFourGiBAndATenthOfTheFreeSpace) {
    const fs::path dir = test::testTempDir();
    const uint64_t limit = defaultCacheSizeLimit(dir / "not" / "created" / "yet");
    EXPECT_GT(limit, 0u);
    EXPECT_LE(limit, uint64_t{4} << 30);
    // Other processes change the free space between the calls: 64 MiB of slack.
    EXPECT_LE(limit, fs::space(dir).available / 10 + (uint64_t{64} << 20));
    EXPECT_GE(limit + (uint64_t{64} << 20), defaultCacheSizeLimit(dir));
    EXPECT_TRUE(listCacheFolder(dir / "absent").entries.empty());
}

}  // namespace
}  // namespace daisy
