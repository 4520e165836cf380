// The cuda backend's host-side logic, tested without a device: the batch plan
// (cuda/batch_plan.h), the double-buffered chunk schedule (cuda/double_buffer.h) and the decoded
// error text of CUDA_CHECK (cuda/cuda_error.h). Oracles: the plan's documented formulas worked by
// hand for an H200-like device (132 SMs, 2048 threads an SM; a kernel of 128 registers a thread
// holds 65536 / (128 * 64) = 8 blocks of 64 an SM), and the schedule's order written out.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cuda/batch_plan.h"
#include "cuda/cuda_error.h"
#include "cuda/double_buffer.h"

namespace daisy {
namespace {

CudaDeviceFacts h200Like() {
    CudaDeviceFacts facts;
    facts.name = "H200-like";
    facts.freeBytes = uint64_t(140) << 30;
    facts.smCount = 132;
    facts.maxThreadsPerSm = 2048;
    facts.blocksPerSm = 8;
    facts.stackBytesPerThread = 4560;
    return facts;
}

TEST(CudaBatchPlan, WavesOfResidentThreads) {
    auto plan = planCudaBatches(h200Like(), 1000000, 20);
    ASSERT_TRUE(plan.ok()) << plan.error().message;
    EXPECT_EQ(plan->blockSize, 64u);
    // 4 waves of 132 SMs x 8 blocks x 64 threads.
    EXPECT_EQ(plan->launchPairs, 4u * 132 * 8 * 64);
    EXPECT_EQ(plan->batchPairs, 4u * plan->launchPairs);
    // The driver's stack reservation: 4560 bytes for each of 132 x 2048 threads.
    EXPECT_EQ(plan->stackBytes, 4560ull * 132 * 2048);
    EXPECT_EQ(plan->deviceBytes, 1000000 + plan->stackBytes + 2 * 16 * plan->launchPairs);
}

TEST(CudaBatchPlan, WatchdogCapsTheWorkOfALaunch) {
    CudaDeviceFacts facts = h200Like();
    facts.watchdog = true;
    // 2^24 units / (4096 points + 16 rays) = 4080 pairs, down to 63 whole blocks.
    auto plan = planCudaBatches(facts, 1000000, 4096 + 16);
    ASSERT_TRUE(plan.ok()) << plan.error().message;
    EXPECT_EQ(plan->launchPairs, 63u * 64);
    // A pair heavier than the cap still gets one block a launch.
    plan = planCudaBatches(facts, 1000000, uint64_t(1) << 30);
    ASSERT_TRUE(plan.ok()) << plan.error().message;
    EXPECT_EQ(plan->launchPairs, 64u);
    // Without a watchdog the same heavy pairs get the full waves.
    facts.watchdog = false;
    plan = planCudaBatches(facts, 1000000, uint64_t(1) << 30);
    ASSERT_TRUE(plan.ok());
    EXPECT_EQ(plan->launchPairs, 4u * 132 * 8 * 64);
}

TEST(CudaBatchPlan, MemoryCapsTheLaunch) {
    CudaDeviceFacts facts = h200Like();
    facts.freeBytes = 10000000;  // 90%: 9e6, less 1e6 of scene: room for 250,000 pairs in 2 slots
    facts.stackBytesPerThread = 0;
    auto plan = planCudaBatches(facts, 1000000, 20);
    ASSERT_TRUE(plan.ok()) << plan.error().message;
    EXPECT_EQ(plan->launchPairs, 250000u / 64 * 64);
    EXPECT_LE(plan->deviceBytes, 9000000u);
}

TEST(CudaBatchPlan, RefusesWhenSceneAndStackDoNotFit) {
    CudaDeviceFacts facts = h200Like();
    facts.freeBytes = uint64_t(1) << 30;  // 1 GiB: less than the 1.15 GiB stack reservation
    auto plan = planCudaBatches(facts, 1000, 20);
    ASSERT_FALSE(plan.ok());
    const std::string& message = plan.error().message;
    EXPECT_NE(message.find("'H200-like'"), std::string::npos) << message;
    EXPECT_NE(message.find("stack"), std::string::npos) << message;
    EXPECT_NE(message.find("--subdivide"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(CudaBatchPlan, EveryPlanIsWholeBlocksWithinMemory) {
    for (int sms : {1, 20, 132}) {
        for (int blocks : {0, 1, 8, 32}) {
            for (uint64_t freeBytes : {uint64_t(1) << 22, uint64_t(1) << 30, uint64_t(1) << 37}) {
                for (bool watchdog : {false, true}) {
                    CudaDeviceFacts facts = h200Like();
                    facts.smCount = sms;
                    facts.blocksPerSm = blocks;
                    facts.freeBytes = freeBytes;
                    facts.stackBytesPerThread = 512;
                    facts.watchdog = watchdog;
                    auto plan = planCudaBatches(facts, 4096, 33);
                    if (!plan) continue;  // too small for the stack: refused, tested above
                    EXPECT_GE(plan->launchPairs, 64u);
                    EXPECT_EQ(plan->launchPairs % 64, 0u);
                    EXPECT_GE(plan->batchPairs, plan->launchPairs);
                    EXPECT_LE(plan->deviceBytes, uint64_t(double(freeBytes) * 0.9));
                }
            }
        }
    }
}

TEST(CudaBatchPlan, TestsMayForceTinySizes) {
    auto plan = planCudaBatches(h200Like(), 1000, 20, CudaBatchLimits{3, 7});
    ASSERT_TRUE(plan.ok());
    EXPECT_EQ(plan->launchPairs, 3u);
    EXPECT_EQ(plan->batchPairs, 7u);
}

TEST(CudaDoubleBuffer, ChunkRanges) {
    EXPECT_EQ(chunkCount(10, 4), 3u);
    EXPECT_EQ(chunkCount(8, 4), 2u);
    EXPECT_EQ(chunkCount(0, 4), 0u);
    const ChunkRange last = chunkRange(2, 4, 10);
    EXPECT_EQ(last.first, 8u);
    EXPECT_EQ(last.count, 2u);
    const ChunkRange middle = chunkRange(1, 4, 10);
    EXPECT_EQ(middle.first, 4u);
    EXPECT_EQ(middle.count, 4u);
}

// A fake device: each slot holds at most one chunk between its submit and its finish.
struct FakeDevice {
    std::vector<std::string> events;
    long inSlot[2] = {-1, -1};
    long failFinishAt = -1;

    Expected<void> run(std::size_t count) {
        return runDoubleBuffered(
            count,
            [&](int slot, std::size_t chunk) -> Expected<void> {
                EXPECT_EQ(inSlot[slot], -1) << "slot " << slot << " reused while busy";
                inSlot[slot] = long(chunk);
                events.push_back("S" + std::to_string(chunk) + "@" + std::to_string(slot));
                return {};
            },
            [&](int slot, std::size_t chunk) -> Expected<void> {
                EXPECT_EQ(inSlot[slot], long(chunk));
                inSlot[slot] = -1;
                events.push_back("F" + std::to_string(chunk) + "@" + std::to_string(slot));
                if (long(chunk) == failFinishAt) return Error{"launch failed"};
                return {};
            });
    }
};

TEST(CudaDoubleBuffer, SubmitsTheNextChunkBeforeFinishingThisOne) {
    FakeDevice device;
    ASSERT_TRUE(device.run(4).ok());
    EXPECT_EQ(
        device.events,
        (std::vector<std::string>{"S0@0", "S1@1", "F0@0", "S2@0", "F1@1", "S3@1", "F2@0", "F3@1"}));
    FakeDevice one;
    ASSERT_TRUE(one.run(1).ok());
    EXPECT_EQ(one.events, (std::vector<std::string>{"S0@0", "F0@0"}));
    FakeDevice none;
    ASSERT_TRUE(none.run(0).ok());
    EXPECT_TRUE(none.events.empty());
}

TEST(CudaDoubleBuffer, FirstErrorStopsTheRun) {
    FakeDevice device;
    device.failFinishAt = 1;
    auto done = device.run(5);
    ASSERT_FALSE(done.ok());
    EXPECT_EQ(done.error().message, "launch failed");
    EXPECT_EQ(device.events, (std::vector<std::string>{"S0@0", "S1@1", "F0@0", "S2@0", "F1@1"}));
}

// cudaError_t values from the CUDA runtime API reference (driver_types.h): 2 is
// cudaErrorMemoryAllocation, 35 cudaErrorInsufficientDriver. Decoding needs no device.
TEST(CudaCheck, MessageDecodesTheErrorAndNamesTheCallAndPlace) {
    const std::string message =
        cudaErrorMessage(2, "cudaMalloc(&p, n)", "/home/me/wt-cuda/cuda/cuda_backend.cpp", 42);
    EXPECT_EQ(message,
              "cuda: cudaMalloc(&p, n) failed: cudaErrorMemoryAllocation (out of memory) at "
              "cuda/cuda_backend.cpp:42");
    const std::string driver = cudaErrorMessage(35, "cudaGetDeviceCount(&n)", "x.cpp", 7);
    EXPECT_NE(driver.find("cudaErrorInsufficientDriver"), std::string::npos) << driver;
    EXPECT_NE(driver.find("at x.cpp:7"), std::string::npos) << driver;
}

}  // namespace
}  // namespace daisy
