#pragma once
// The viewer's few Vulkan resources (STYLE.md rule 6: plain handle structs, free functions):
// host-visible buffers (vertex data, screenshot read-back) and device-local images (depth).
// Unlike vulkan/buffers.h these need no buffer device address, so they work on any Vulkan 1.2
// device.
#include <volk.h>

#include "core/expected.h"
#include "vulkan/context.h"

namespace daisy::viewer {

struct HostBuffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize bytes = 0;
    void* mapped = nullptr;  // host-visible, coherent, mapped for the buffer's life
};

// A mapped buffer of `bytes` (> 0) with `usage`. An Error (VK_CHECK) when the device cannot make
// it; nothing is left allocated then.
Expected<HostBuffer> createHostBuffer(const VulkanContext& context, VkDeviceSize bytes,
                                      VkBufferUsageFlags usage);
void destroyHostBuffer(const VulkanContext& context, HostBuffer& buffer);

struct DeviceImage {
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
};

// A 2D device-local image with one mip level and its view of `aspect`. An Error (VK_CHECK) when
// the device cannot make it; nothing is left allocated then.
Expected<DeviceImage> createDeviceImage(const VulkanContext& context, uint32_t width,
                                        uint32_t height, VkFormat format, VkImageUsageFlags usage,
                                        VkImageAspectFlags aspect);
void destroyDeviceImage(const VulkanContext& context, DeviceImage& image);

}  // namespace daisy::viewer
