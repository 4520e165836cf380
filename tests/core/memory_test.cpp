// core/memory.h against the kernel's own bookkeeping: touching 64 MiB raises the peak by at least
// that much, and after the block is returned (a 64 MiB malloc is its own mmap, unmapped on free)
// a reset brings the peak back down to the current resident size.
#include "core/memory.h"

#include <gtest/gtest.h>

#include <cstring>
#include <memory>

namespace daisy {
namespace {

constexpr uint64_t kBlock = 64ull << 20;

TEST(Memory, PeakFollowsTouchedPagesAndResets) {
    ASSERT_TRUE(resetPeakResidentBytes());
    const uint64_t before = peakResidentBytes();
    ASSERT_GT(before, 0u);
    {
        auto block = std::make_unique<char[]>(kBlock);
        std::memset(block.get(), 1, kBlock);
        EXPECT_GE(peakResidentBytes(), before + kBlock - (1ull << 20));
        EXPECT_EQ(block[kBlock - 1], 1);
    }
    const uint64_t withBlock = peakResidentBytes();
    ASSERT_TRUE(resetPeakResidentBytes());
    EXPECT_LT(peakResidentBytes(), withBlock - kBlock / 2);
}

}  // namespace
}  // namespace daisy
