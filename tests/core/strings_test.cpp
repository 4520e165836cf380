#include "core/strings.h"

#include <gtest/gtest.h>

#include "core/expected.h"

namespace daisy {
namespace {

TEST(Strings, ParseByteSizeUsesBinaryMultiples) {
    uint64_t bytes = 0;
    ASSERT_TRUE(parseByteSize("1000", bytes));
    EXPECT_EQ(bytes, 1000u);
    ASSERT_TRUE(parseByteSize("512M", bytes));
    EXPECT_EQ(bytes, 512ull << 20);
    ASSERT_TRUE(parseByteSize("2G", bytes));
    EXPECT_EQ(bytes, 2ull << 30);
    ASSERT_TRUE(parseByteSize("1.5GiB", bytes));
    EXPECT_EQ(bytes, 3ull << 29);
    ASSERT_TRUE(parseByteSize("64 MiB", bytes));
    EXPECT_EQ(bytes, 64ull << 20);
    ASSERT_TRUE(parseByteSize("3kb", bytes));
    EXPECT_EQ(bytes, 3072u);
}

TEST(Strings, ParseByteSizeRejectsNonsense) {
    uint64_t bytes = 0;
    for (const char* bad : {"", "G", "-1G", "12X", "1e30", "nan", "5Gx", "inf"}) {
        EXPECT_FALSE(parseByteSize(bad, bytes)) << bad;
    }
}

// Names from files print on one line and whole: control characters become C escapes.
TEST(Strings, PrintableEscapesControlCharacters) {
    EXPECT_EQ(printable("floor"), "floor");
    EXPECT_EQ(printable("flo\nor\nerror: fake"), "flo\\nor\\nerror: fake");
    EXPECT_EQ(printable(std::string("a\0b\t\r\x1b\x7f", 7)), "a\\0b\\t\\r\\x1b\\x7f");
    EXPECT_EQ(printable("caf\xc3\xa9 \\n"), "caf\xc3\xa9 \\n");  // UTF-8 and backslashes kept
}

TEST(Strings, FormatBytes) {
    EXPECT_EQ(formatBytes(800), "800 B");
    EXPECT_EQ(formatBytes(1536), "1.50 KiB");
    EXPECT_EQ(formatBytes(512.0 * 1024 * 1024), "512 MiB");
    EXPECT_EQ(formatBytes(24.0 * 1024 * 1024 * 1024), "24.0 GiB");
}

TEST(Strings, NumbersReadBackExactlyAndShort) {
    EXPECT_EQ(formatNumber(1.2), "1.2");
    EXPECT_EQ(formatNumber(-0.1), "-0.1");
    EXPECT_EQ(formatNumber(200000.0), "200000");
    EXPECT_EQ(formatNumber(1e-300), "1e-300");
    EXPECT_EQ(formatNumber(1.93434568673662, 6), "1.93435");
    EXPECT_EQ(concat("x=", 0.1, " n=", 3), "x=0.1 n=3");
    EXPECT_EQ(formatCount(478306937), "478,306,937");
    EXPECT_EQ(formatCount(999), "999");
    EXPECT_EQ(formatCount(1000), "1,000");
}

TEST(Expected, CarriesValueOrError) {
    Expected<int> good = 7;
    ASSERT_TRUE(good);
    EXPECT_EQ(*good, 7);
    Expected<int> bad = Error{"boom"};
    ASSERT_FALSE(bad);
    EXPECT_EQ(withContext(bad.error(), "file.gltf").message, "file.gltf: boom");
    Expected<void> fine;
    EXPECT_TRUE(fine);
}

}  // namespace
}  // namespace daisy
