// VK_CHECK (src/vulkan/vk_check.h): a failing VkResult returns an Error from the enclosing
// function naming the call, the decoded result and file:line, as CUDA_CHECK does, instead of
// aborting; the call is evaluated once. Through the public API: a buffer larger than the driver
// allows (Mesa lavapipe refuses any buffer over 4 GiB - 1 with VK_ERROR_OUT_OF_DEVICE_MEMORY;
// other drivers fail its memory allocation) comes back as that Error, and the device stays
// usable afterwards.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/expected.h"
#include "test_util.h"

#ifdef DAISY_HAVE_VULKAN
#include "vulkan/buffers.h"
#include "vulkan/context.h"
#include "vulkan/vk_check.h"
#endif

namespace daisy {
namespace {

#ifdef DAISY_HAVE_VULKAN

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

TEST(VulkanCheckTest, AFailingCallReturnsAnErrorNamingTheCallAndTheResult) {
    int calls = 0;
    const auto deviceLost = [&] {
        ++calls;
        return VK_ERROR_DEVICE_LOST;
    };
    bool after = false;
    constexpr int kLine = __LINE__ + 2;
    const auto run = [&]() -> Expected<void> {
        VK_CHECK(deviceLost());
        after = true;
        return {};
    };
    const Expected<void> result = run();
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(calls, 1);
    EXPECT_FALSE(after);
    const std::string& message = result.error().message;
    EXPECT_EQ(message.rfind("vulkan: deviceLost() failed: VK_ERROR_DEVICE_LOST at ", 0), 0u)
        << message;
    EXPECT_TRUE(contains(message, "vk_check_test.cpp:" + std::to_string(kLine))) << message;
}

TEST(VulkanCheckTest, SuccessContinuesAndValuesPassThrough) {
    int calls = 0;
    const auto success = [&] {
        ++calls;
        return VK_SUCCESS;
    };
    const auto run = [&]() -> Expected<int> {
        VK_CHECK(success());
        return 7;
    };
    const Expected<int> result = run();
    ASSERT_TRUE(result.ok()) << result.error().message;
    EXPECT_EQ(*result, 7);
    EXPECT_EQ(calls, 1);
}

// Every result but VK_SUCCESS fails (VK_SUBOPTIMAL_KHR and the like are the caller's to handle
// first), and a value the name table lacks is still decoded.
TEST(VulkanCheckTest, OtherResultsAreDecoded) {
    const auto check = [](VkResult code) -> Expected<void> {
        VK_CHECK(code);
        return {};
    };
    EXPECT_TRUE(contains(check(VK_INCOMPLETE).error().message, "failed: VK_INCOMPLETE at "));
    EXPECT_TRUE(contains(check(VK_ERROR_OUT_OF_DATE_KHR).error().message,
                         "failed: VK_ERROR_OUT_OF_DATE_KHR at "));
    EXPECT_TRUE(
        contains(check(VkResult(-123456)).error().message, "failed: VkResult(-123456) at "));
}

// The file is shortened to the source tree's own path, whatever the checkout is called.
TEST(VulkanCheckTest, MessageNamesThePlaceInTheSourceTree) {
    EXPECT_EQ(vkErrorMessage(VK_ERROR_OUT_OF_DEVICE_MEMORY,
                             "vkAllocateMemory(context.device, &info, nullptr, &memory)",
                             "/home/someone/src/daisy/src/vulkan/buffers.cpp", 61),
              "vulkan: vkAllocateMemory(context.device, &info, nullptr, &memory) failed: "
              "VK_ERROR_OUT_OF_DEVICE_MEMORY at src/vulkan/buffers.cpp:61");
    EXPECT_EQ(vkErrorMessage(VK_ERROR_DEVICE_LOST, "f()", "elsewhere/x.cpp", 3),
              "vulkan: f() failed: VK_ERROR_DEVICE_LOST at elsewhere/x.cpp:3");
}

TEST(VulkanCheckTest, AnOversizedBufferIsAnErrorAndTheDeviceStaysUsable) {
    auto context = createContext("");
    if (!context) DAISY_SKIP_WITHOUT_VULKAN(context.error().message);
    const VkDeviceSize tooLarge = VkDeviceSize(1) << 40;  // 1 TiB
    auto buffer = createBuffer(*context, tooLarge);
    ASSERT_FALSE(buffer.ok()) << "a 1 TiB buffer was made on '" << context->properties.deviceName
                              << "'";
    const std::string& message = buffer.error().message;
    EXPECT_EQ(message.rfind("vulkan: vk", 0), 0u) << message;
    EXPECT_TRUE(contains(message, " failed: VK_ERROR_OUT_OF_")) << message;
    EXPECT_TRUE(contains(message, " at src/vulkan/buffers.cpp:")) << message;

    // The failure left nothing half-made: a small buffer round-trips its bytes.
    auto small = createBuffer(*context, 64);
    ASSERT_TRUE(small.ok()) << small.error().message;
    const std::vector<uint32_t> sent{1, 2, 3, 4};
    std::vector<uint32_t> received(sent.size(), 0);
    ASSERT_TRUE(upload(*context, *small, sent.data(), sent.size() * sizeof(uint32_t)).ok());
    ASSERT_TRUE(
        download(*context, *small, received.data(), received.size() * sizeof(uint32_t)).ok());
    EXPECT_EQ(received, sent);
    destroyBuffer(*context, *small);
    destroyContext(*context);
}

#else

TEST(VulkanCheckTest, NotBuilt) {
    DAISY_SKIP_WITHOUT_VULKAN("built with DAISY_ENABLE_VULKAN=OFF");
}

#endif

}  // namespace
}  // namespace daisy
