#include "viewer/gpu_resources.h"

#include "core/check.h"
#include "vulkan/vk_check.h"

namespace daisy::viewer {
namespace {

uint32_t memoryType(const VulkanContext& context, uint32_t typeBits, VkMemoryPropertyFlags wanted) {
    for (uint32_t k = 0; k < context.memory.memoryTypeCount; ++k) {
        if ((typeBits & (1u << k)) &&
            (context.memory.memoryTypes[k].propertyFlags & wanted) == wanted)
            return k;
    }
    DAISY_CHECK(false && "no Vulkan memory type with the wanted properties");
    return 0;
}

VkDeviceMemory allocate(const VulkanContext& context, const VkMemoryRequirements& requirements,
                        VkMemoryPropertyFlags wanted) {
    VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    info.allocationSize = requirements.size;
    info.memoryTypeIndex = memoryType(context, requirements.memoryTypeBits, wanted);
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VK_CHECK(vkAllocateMemory(context.device, &info, nullptr, &memory));
    return memory;
}

}  // namespace

HostBuffer createHostBuffer(const VulkanContext& context, VkDeviceSize bytes,
                            VkBufferUsageFlags usage) {
    DAISY_CHECK(bytes > 0);
    HostBuffer buffer;
    buffer.bytes = bytes;
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = bytes;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VK_CHECK(vkCreateBuffer(context.device, &info, nullptr, &buffer.buffer));
    VkMemoryRequirements requirements;
    vkGetBufferMemoryRequirements(context.device, buffer.buffer, &requirements);
    buffer.memory =
        allocate(context, requirements,
                 VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    VK_CHECK(vkBindBufferMemory(context.device, buffer.buffer, buffer.memory, 0));
    VK_CHECK(vkMapMemory(context.device, buffer.memory, 0, bytes, 0, &buffer.mapped));
    return buffer;
}

void destroyHostBuffer(const VulkanContext& context, HostBuffer& buffer) {
    if (buffer.buffer) vkDestroyBuffer(context.device, buffer.buffer, nullptr);
    if (buffer.memory) vkFreeMemory(context.device, buffer.memory, nullptr);
    buffer = HostBuffer{};
}

DeviceImage createDeviceImage(const VulkanContext& context, uint32_t width, uint32_t height,
                              VkFormat format, VkImageUsageFlags usage, VkImageAspectFlags aspect) {
    DeviceImage image;
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
    image.memory = allocate(context, requirements, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    VK_CHECK(vkBindImageMemory(context.device, image.image, image.memory, 0));
    VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    viewInfo.image = image.image;
    viewInfo.viewType = VK_IMAGE_VIEW_TYPE_2D;
    viewInfo.format = format;
    viewInfo.subresourceRange = {aspect, 0, 1, 0, 1};
    VK_CHECK(vkCreateImageView(context.device, &viewInfo, nullptr, &image.view));
    return image;
}

void destroyDeviceImage(const VulkanContext& context, DeviceImage& image) {
    if (image.view) vkDestroyImageView(context.device, image.view, nullptr);
    if (image.image) vkDestroyImage(context.device, image.image, nullptr);
    if (image.memory) vkFreeMemory(context.device, image.memory, nullptr);
    image = DeviceImage{};
}

}  // namespace daisy::viewer
