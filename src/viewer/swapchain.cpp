#include "viewer/swapchain.h"

#include <algorithm>

#include "vulkan/vk_check.h"

namespace daisy::viewer {
namespace {

// Destroys what hangs off the images, keeping the swapchain handle itself.
void destroyImageResources(const VulkanContext& context, Swapchain& swapchain) {
    for (VkFramebuffer framebuffer : swapchain.framebuffers)
        vkDestroyFramebuffer(context.device, framebuffer, nullptr);
    for (VkImageView view : swapchain.views)
        vkDestroyImageView(context.device, view, nullptr);
    for (VkSemaphore semaphore : swapchain.renderFinished)
        vkDestroySemaphore(context.device, semaphore, nullptr);
    destroyDeviceImage(context, swapchain.depth);
    swapchain.framebuffers.clear();
    swapchain.views.clear();
    swapchain.renderFinished.clear();
    swapchain.images.clear();
}

}  // namespace

SurfaceFormats chooseSurfaceFormats(const VulkanContext& context, VkSurfaceKHR surface) {
    uint32_t count = 0;
    vkGetPhysicalDeviceSurfaceFormatsKHR(context.physicalDevice, surface, &count, nullptr);
    std::vector<VkSurfaceFormatKHR> offered(count);
    vkGetPhysicalDeviceSurfaceFormatsKHR(context.physicalDevice, surface, &count, offered.data());
    SurfaceFormats formats;
    formats.colour = offered.empty()
        ? VkSurfaceFormatKHR{VK_FORMAT_B8G8R8A8_UNORM, VK_COLOR_SPACE_SRGB_NONLINEAR_KHR}
        : offered[0];
    for (const VkSurfaceFormatKHR& format : offered) {
        if ((format.format == VK_FORMAT_B8G8R8A8_UNORM ||
             format.format == VK_FORMAT_R8G8B8A8_UNORM) &&
            format.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) {
            formats.colour = format;
            break;
        }
    }
    const VkFormat colour = formats.colour.format;
    formats.encodeSrgb = colour == VK_FORMAT_B8G8R8A8_UNORM || colour == VK_FORMAT_R8G8B8A8_UNORM;
    formats.bgr = colour == VK_FORMAT_B8G8R8A8_UNORM || colour == VK_FORMAT_B8G8R8A8_SRGB;
    for (VkFormat depth : {VK_FORMAT_D32_SFLOAT, VK_FORMAT_X8_D24_UNORM_PACK32,
                           VK_FORMAT_D24_UNORM_S8_UINT, VK_FORMAT_D16_UNORM}) {
        VkFormatProperties properties;
        vkGetPhysicalDeviceFormatProperties(context.physicalDevice, depth, &properties);
        if (properties.optimalTilingFeatures & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT) {
            formats.depth = depth;
            break;
        }
    }
    return formats;
}

Expected<VkRenderPass> createRenderPass(const VulkanContext& context,
                                        const SurfaceFormats& formats) {
    VkAttachmentDescription attachments[2]{};
    attachments[0].format = formats.colour.format;
    attachments[0].samples = VK_SAMPLE_COUNT_1_BIT;
    attachments[0].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    attachments[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    attachments[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    attachments[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    attachments[0].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    attachments[0].finalLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
    attachments[1].format = formats.depth;
    attachments[1].samples = VK_SAMPLE_COUNT_1_BIT;
    attachments[1].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    attachments[1].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    attachments[1].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    attachments[1].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    attachments[1].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    attachments[1].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    VkAttachmentReference colourRef{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkAttachmentReference depthRef{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = 1;
    subpass.pColorAttachments = &colourRef;
    subpass.pDepthStencilAttachment = &depthRef;
    // The colour write waits for the acquire semaphore (signalled at colour output), and the
    // depth clear for the previous frame's depth use (one depth image for all frames).
    VkSubpassDependency dependency{};
    dependency.srcSubpass = VK_SUBPASS_EXTERNAL;
    dependency.dstSubpass = 0;
    dependency.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
        VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    dependency.dstStageMask = dependency.srcStageMask;
    dependency.srcAccessMask = VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    dependency.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
        VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    info.attachmentCount = 2;
    info.pAttachments = attachments;
    info.subpassCount = 1;
    info.pSubpasses = &subpass;
    info.dependencyCount = 1;
    info.pDependencies = &dependency;
    VkRenderPass renderPass = VK_NULL_HANDLE;
    VK_CHECK(vkCreateRenderPass(context.device, &info, nullptr, &renderPass));
    return renderPass;
}

Expected<bool> createSwapchain(const VulkanContext& context, VkSurfaceKHR surface,
                               const SurfaceFormats& formats, VkRenderPass renderPass,
                               uint32_t width, uint32_t height, Swapchain& swapchain) {
    VkSurfaceCapabilitiesKHR capabilities;
    VK_CHECK(
        vkGetPhysicalDeviceSurfaceCapabilitiesKHR(context.physicalDevice, surface, &capabilities));
    VkExtent2D extent = capabilities.currentExtent;
    if (extent.width == 0xffffffffu) {
        extent.width =
            std::clamp(width, capabilities.minImageExtent.width, capabilities.maxImageExtent.width);
        extent.height = std::clamp(height, capabilities.minImageExtent.height,
                                   capabilities.maxImageExtent.height);
    }
    if (extent.width == 0 || extent.height == 0) return false;

    uint32_t imageCount = std::max(capabilities.minImageCount + 1, 2u);
    if (capabilities.maxImageCount > 0)
        imageCount = std::min(imageCount, capabilities.maxImageCount);
    // FIFO (vsync) is always there (Vulkan spec) and does not spin a core on a real display.
    const VkPresentModeKHR presentMode = VK_PRESENT_MODE_FIFO_KHR;
    const bool transferSource =
        (capabilities.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT) != 0;

    VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    info.surface = surface;
    info.minImageCount = imageCount;
    info.imageFormat = formats.colour.format;
    info.imageColorSpace = formats.colour.colorSpace;
    info.imageExtent = extent;
    info.imageArrayLayers = 1;
    info.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT |
        (transferSource ? VK_IMAGE_USAGE_TRANSFER_SRC_BIT : 0);
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = capabilities.currentTransform;
    info.compositeAlpha = (capabilities.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
        ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
        : VkCompositeAlphaFlagBitsKHR(capabilities.supportedCompositeAlpha &
                                      -capabilities.supportedCompositeAlpha);
    info.presentMode = presentMode;
    info.clipped = VK_TRUE;
    info.oldSwapchain = swapchain.swapchain;
    VkSwapchainKHR created = VK_NULL_HANDLE;
    VK_CHECK(vkCreateSwapchainKHR(context.device, &info, nullptr, &created));
    destroySwapchain(context, swapchain);
    swapchain.swapchain = created;
    swapchain.extent = extent;
    swapchain.minImageCount = imageCount;
    swapchain.transferSource = transferSource;

    uint32_t count = 0;
    VK_CHECK(vkGetSwapchainImagesKHR(context.device, created, &count, nullptr));
    swapchain.images.resize(count);
    VK_CHECK(vkGetSwapchainImagesKHR(context.device, created, &count, swapchain.images.data()));
    auto depth =
        createDeviceImage(context, extent.width, extent.height, formats.depth,
                          VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, VK_IMAGE_ASPECT_DEPTH_BIT);
    if (!depth) return depth.error();
    swapchain.depth = *depth;
    for (VkImage image : swapchain.images) {
        VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        viewInfo.image = image;
        viewInfo.viewType = VK_IMAGE_VIEW_TYPE_2D;
        viewInfo.format = formats.colour.format;
        viewInfo.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        VkImageView view = VK_NULL_HANDLE;
        VK_CHECK(vkCreateImageView(context.device, &viewInfo, nullptr, &view));
        swapchain.views.push_back(view);
        VkImageView attachments[2] = {view, swapchain.depth.view};
        VkFramebufferCreateInfo framebufferInfo{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
        framebufferInfo.renderPass = renderPass;
        framebufferInfo.attachmentCount = 2;
        framebufferInfo.pAttachments = attachments;
        framebufferInfo.width = extent.width;
        framebufferInfo.height = extent.height;
        framebufferInfo.layers = 1;
        VkFramebuffer framebuffer = VK_NULL_HANDLE;
        VK_CHECK(vkCreateFramebuffer(context.device, &framebufferInfo, nullptr, &framebuffer));
        swapchain.framebuffers.push_back(framebuffer);
        VkSemaphoreCreateInfo semaphoreInfo{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VkSemaphore semaphore = VK_NULL_HANDLE;
        VK_CHECK(vkCreateSemaphore(context.device, &semaphoreInfo, nullptr, &semaphore));
        swapchain.renderFinished.push_back(semaphore);
    }
    return true;
}

void destroySwapchain(const VulkanContext& context, Swapchain& swapchain) {
    destroyImageResources(context, swapchain);
    if (swapchain.swapchain) vkDestroySwapchainKHR(context.device, swapchain.swapchain, nullptr);
    swapchain.swapchain = VK_NULL_HANDLE;
}

}  // namespace daisy::viewer
