// The viewer's Vulkan resources (viewer/gpu_resources.h) report a device that cannot make them
// as an Error naming the call and the VkResult (VK_CHECK, src/vulkan/vk_check.h), which `daisy
// view` prints before exiting 2, rather than aborting. Mesa lavapipe refuses any buffer over
// 4 GiB - 1 (VK_ERROR_OUT_OF_DEVICE_MEMORY); other drivers fail the allocation. Needs a device
// only, no window: the compute context serves.
#if DAISY_HAVE_VIEWER
#include "viewer/gpu_resources.h"

#include <gtest/gtest.h>

#include <string>

#include "test_util.h"
#include "vulkan/context.h"

namespace daisy::viewer {
namespace {

TEST(ViewerGpuResourcesTest, AnOversizedHostBufferIsAnError) {
    auto context = createContext("");
    if (!context) DAISY_SKIP_WITHOUT_VULKAN(context.error().message);
    auto buffer =
        createHostBuffer(*context, VkDeviceSize(1) << 40, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    ASSERT_FALSE(buffer.ok()) << "a 1 TiB host buffer was made on '"
                              << context->properties.deviceName << "'";
    const std::string& message = buffer.error().message;
    EXPECT_EQ(message.rfind("vulkan: vk", 0), 0u) << message;
    EXPECT_NE(message.find(" failed: VK_ERROR_OUT_OF_"), std::string::npos) << message;
    EXPECT_NE(message.find(" at src/viewer/gpu_resources.cpp:"), std::string::npos) << message;

    // What does fit is still made, mapped and destroyed.
    auto small = createHostBuffer(*context, 256, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    ASSERT_TRUE(small.ok()) << small.error().message;
    EXPECT_NE(small->mapped, nullptr);
    destroyHostBuffer(*context, *small);
    destroyContext(*context);
}

}  // namespace
}  // namespace daisy::viewer
#endif
