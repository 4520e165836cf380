// Progress reporting helpers (DESIGN.md section 9: stage, percent, rate, ETA) and the
// all-or-nothing file writer. Oracles: the formats written out by hand.
#include "core/progress.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/atomic_file.h"
#include "test_util.h"

namespace daisy {
namespace {

TEST(Progress, DurationsAndRatesForHumans) {
    EXPECT_EQ(formatDuration(3.24), "3.2 s");
    EXPECT_EQ(formatDuration(42), "42 s");
    EXPECT_EQ(formatDuration(245), "4 min 05 s");
    EXPECT_EQ(formatDuration(3720), "1 h 02 min");
    EXPECT_EQ(formatSi(78), "78 ");
    EXPECT_EQ(formatSi(1234567), "1.23 M ");
}

TEST(Progress, CountsFromManyThreadsWhenSilent) {
    Progress progress("stage", 1000, "pairs", /*enabled=*/false);
    for (int k = 0; k < 10; ++k)
        progress.advance(100);
    EXPECT_EQ(progress.done(), 1000u);
    progress.finish();
    progress.finish();  // idempotent
}

TEST(AtomicFile, FailureLeavesNothingBehind) {
    const auto dir = test::testTempDir();
    const std::string path = (dir / "out.txt").string();
    auto failed = writeFileAtomically(path, [](std::FILE* file) -> std::string {
        std::fputs("partial", file);
        return "the producer gave up";
    });
    ASSERT_FALSE(failed.ok());
    EXPECT_EQ(failed.error().message, path + ": the producer gave up");
    EXPECT_TRUE(std::filesystem::is_empty(dir));

    ASSERT_TRUE(writeFileAtomically(path, [](std::FILE* file) -> std::string {
                    std::fputs("whole", file);
                    return "";
                }).ok());
    std::ifstream in(path);
    std::string text;
    in >> text;
    EXPECT_EQ(text, "whole");
}

}  // namespace
}  // namespace daisy
