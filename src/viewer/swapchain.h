#pragma once
// The window's swapchain: images, their views and framebuffers, one depth
// image, and one "rendering finished" semaphore per image (a present may still wait on the
// previous one when the frame in flight that used it has finished). Made again, reusing the old
// swapchain, on resize and on VK_ERROR_OUT_OF_DATE_KHR / VK_SUBOPTIMAL_KHR.
#include <volk.h>

#include <vector>

#include "core/expected.h"
#include "viewer/gpu_resources.h"
#include "vulkan/context.h"

namespace daisy::viewer {

struct Swapchain {
    VkSwapchainKHR swapchain = VK_NULL_HANDLE;
    VkExtent2D extent{0, 0};
    std::vector<VkImage> images;
    std::vector<VkImageView> views;
    std::vector<VkFramebuffer> framebuffers;
    std::vector<VkSemaphore> renderFinished;  // per image
    DeviceImage depth;
    uint32_t minImageCount = 2;
    bool transferSource = false;  // images can be copied from (screenshots)
};

// The formats of the window's pictures: 8-bit UNORM colour when the surface offers it (the
// shaders then apply the sRGB curve themselves, and Dear ImGui's colours are right), else the
// first format offered; and a depth format of the device.
struct SurfaceFormats {
    VkSurfaceFormatKHR colour{};
    VkFormat depth = VK_FORMAT_UNDEFINED;
    bool encodeSrgb = false;  // colour is UNORM: shaders encode
    bool bgr = false;  // colour's bytes are B, G, R, A
};
SurfaceFormats chooseSurfaceFormats(const VulkanContext& context, VkSurfaceKHR surface);

// One subpass: colour (cleared to black, then presented) and depth (cleared to 0: reverse-Z).
Expected<VkRenderPass> createRenderPass(const VulkanContext& context,
                                        const SurfaceFormats& formats);

// (Re)creates `swapchain` for a framebuffer of width x height pixels (clamped to the surface's
// limits); the previous swapchain, if any, is handed to the driver and destroyed. False when the
// surface's extent is 0 (a minimised window): nothing is created then. An Error (VK_CHECK) when a
// call fails; what was made stays in `swapchain` for destroySwapchain.
Expected<bool> createSwapchain(const VulkanContext& context, VkSurfaceKHR surface,
                               const SurfaceFormats& formats, VkRenderPass renderPass,
                               uint32_t width, uint32_t height, Swapchain& swapchain);
void destroySwapchain(const VulkanContext& context, Swapchain& swapchain);

}  // namespace daisy::viewer
