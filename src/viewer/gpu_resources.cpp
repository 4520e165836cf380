#include "viewer/gpu_resources.h"

#include "core/check.h"
#include "core/strings.h"
#include "vulkan/vk_check.h"

namespace daisy::viewer {
namespace {

Expected<uint32_t> memoryType(const VulkanContext& context, uint32_t typeBits,
                              VkMemoryPropertyFlags wanted) {
    for (uint32_t k = 0; k < context.memory.memoryTypeCount; ++k) {
        if ((typeBits & (1u << k)) &&
            (context.memory.memoryTypes[k].propertyFlags & wanted) == wanted)
            return k;
    }
    const bool host = (wanted & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) != 0;
    return Error{concat("vulkan: device '", context.properties.deviceName, "' offers no ",
                        host ? "host-visible coherent" : "device-local",
                        " memory for this resource")};
}

Expected<VkDeviceMemory> allocate(const VulkanContext& context,
                                  const VkMemoryRequirements& requirements,
                                  VkMemoryPropertyFlags wanted) {
    auto type = memoryType(context, requirements.memoryTypeBits, wanted);
    if (!type) return type.error();
    VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    info.allocationSize = requirements.size;
    info.memoryTypeIndex = *type;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VK_CHECK(vkAllocateMemory(context.device, &info, nullptr, &memory));
    return memory;
}

// The buffer, memory and mapping of createHostBuffer into `buffer`; what it made stays there when
// it fails, for the caller to destroy.
Expected<void> makeHostBuffer(const VulkanContext& context, VkBufferUsageFlags usage,
                              HostBuffer& buffer) {
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = buffer.bytes;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VK_CHECK(vkCreateBuffer(context.device, &info, nullptr, &buffer.buffer));
    VkMemoryRequirements requirements;
    vkGetBufferMemoryRequirements(context.device, buffer.buffer, &requirements);
    auto memory =
        allocate(context, requirements,
                 VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    if (!memory) return memory.error();
    buffer.memory = *memory;
    VK_CHECK(vkBindBufferMemory(context.device, buffer.buffer, buffer.memory, 0));
    VK_CHECK(vkMapMemory(context.device, buffer.memory, 0, buffer.bytes, 0, &buffer.mapped));
    return {};
}

// The image, memory and view of createDeviceImage into `image`, as makeHostBuffer.
Expected<void> makeDeviceImage(const VulkanContext& context, uint32_t width, uint32_t height,
                               VkFormat format, VkImageUsageFlags usage, VkImageAspectFlags aspect,
                               DeviceImage& image) {
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {width, height, 1};
    info.mipLevels = 1;
    info.arrayLayers = 1;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VK_CHECK(vkCreateImage(context.device, &info, nullptr, &image.image));
    VkMemoryRequirements requirements;
    vkGetImageMemoryRequirements(context.device, image.image, &requirements);
    auto memory = allocate(context, requirements, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    if (!memory) return memory.error();
    image.memory = *memory;
    VK_CHECK(vkBindImageMemory(context.device, image.image, image.memory, 0));
    VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    viewInfo.image = image.image;
    viewInfo.viewType = VK_IMAGE_VIEW_TYPE_2D;
    viewInfo.format = format;
    viewInfo.subresourceRange = {aspect, 0, 1, 0, 1};
    VK_CHECK(vkCreateImageView(context.device, &viewInfo, nullptr, &image.view));
    return {};
}

}  // namespace

Expected<HostBuffer> createHostBuffer(const VulkanContext& context, VkDeviceSize bytes,
                                      VkBufferUsageFlags usage) {
    DAISY_CHECK(bytes > 0);
    HostBuffer buffer;
    buffer.bytes = bytes;
    if (auto made = makeHostBuffer(context, usage, buffer); !made) {
        destroyHostBuffer(context, buffer);
        return made.error();
    }
    return buffer;
}

void destroyHostBuffer(const VulkanContext& context, HostBuffer& buffer) {
    if (buffer.buffer) vkDestroyBuffer(context.device, buffer.buffer, nullptr);
    if (buffer.memory) vkFreeMemory(context.device, buffer.memory, nullptr);
    buffer = HostBuffer{};
}

Expected<DeviceImage> createDeviceImage(const VulkanContext& context, uint32_t width,
                                        uint32_t height, VkFormat format, VkImageUsageFlags usage,
                                        VkImageAspectFlags aspect) {
    DeviceImage image;
    if (auto made = makeDeviceImage(context, width, height, format, usage, aspect, image); !made) {
        destroyDeviceImage(context, image);
        return made.error();
    }
    return image;
}

void destroyDeviceImage(const VulkanContext& context, DeviceImage& image) {
    if (image.view) vkDestroyImageView(context.device, image.view, nullptr);
    if (image.image) vkDestroyImage(context.device, image.image, nullptr);
    if (image.memory) vkFreeMemory(context.device, image.memory, nullptr);
    image = DeviceImage{};
}

}  // namespace daisy::viewer
